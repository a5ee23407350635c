// The buffers every meshlet extraction pass binds, in one layout (tessera_data::meshlets::
// gpu_layout describes their content; host side: iso::meshlets::buffers).
// Needs iso/direct/block_list.glsl.

// tessera_data::meshlets::Meshlet: scalar arrays, not vec3, so std430 packs it in 19 words.
struct Meshlet {
    uint vertex_offset;
    uint vertex_count;
    uint triangle_offset;
    uint triangle_count;
    float aabb_min[3];
    float aabb_max[3];
    uint block_origin[3];
    uint subblock_origin[3];
    uint subblock_size[3];
};

// Totals reserved so far (they keep counting past the capacities) and MESHLET_OVERFLOW_* bits.
struct MeshletCounters {
    uint meshlets;
    uint vertices;
    uint triangles;
    uint overflow;
};

// A block's reservation outran a capacity: grow the buffers and extract again.
const uint MESHLET_OVERFLOW_CAPACITY = 1u;
// An extraction counted otherwise than its region analysis: a defect, never a retry.
const uint MESHLET_OVERFLOW_MISMATCH = 2u;

layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) readonly buffer Blocks { BlockListHeader block_header; uint occupied_blocks[]; };
layout(binding = 2) coherent buffer Counters { MeshletCounters counters; };
layout(binding = 3) writeonly buffer Meshlets { Meshlet meshlets[]; };
layout(binding = 4) writeonly buffer Positions { float positions[]; };
layout(binding = 5) writeonly buffer Normals { float normals[]; };
// Three local indices per triangle, a byte each, four to a word.
layout(binding = 6) writeonly buffer LocalIndices { uint local_index_words[]; };
// Per entry of the occupied-block list: first meshlet, meshlet count.
layout(binding = 7) writeonly buffer BlockMeshlets { uvec2 block_meshlets[]; };
