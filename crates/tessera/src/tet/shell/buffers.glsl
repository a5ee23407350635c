// The buffers every shell-traversal pass binds first (host side: `ShellBuffers::bindings`).
layout(binding = 0) readonly buffer Vertices { vec4 vertices[]; };  // world xyz, w the scalar as loaded
// The tets in the layout TET_LAYOUT, TET_WORDS 32-bit words each (tet/shell/layout.glsl).
layout(binding = 1) readonly buffer Tets { uint tet_words[]; };
// Shell triangles in BVH leaf order: outward-wound vertex ids, and in w the tet behind.
layout(binding = 2) readonly buffer ShellFaces { uvec4 shell_faces[]; };
struct BvhNode {
    vec3 lo;
    uint first;  // inner node: first child (the second follows); leaf: first shell face
    vec3 hi;
    uint count;  // shell faces of a leaf; 0 for an inner node
};
layout(binding = 3) readonly buffer Bvh { BvhNode bvh_nodes[]; };
// The absorption table at ABSORPTION_TABLE, the emission table at EMISSION_TABLE (tet/table.glsl).
layout(binding = 4) readonly buffer Table { vec4 table[]; };
// Traversal counters at the STAT_* indices.
layout(binding = 5) buffer Stats { uint stats[]; };

const uint NO_NEIGHBOUR = 0xffffffffu;
