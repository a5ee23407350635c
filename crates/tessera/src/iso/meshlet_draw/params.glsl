// Push constants of every meshlet draw pass (host side: iso::meshlet_draw::MeshletDrawParams).
layout(push_constant) uniform MeshletDrawParams {
    mat4 grid_to_clip;
    vec3 eye_world;
    uint bounds;             // MESHLET_BOUNDS_*: the box frustum culling tests
    vec4 grid_to_world;      // xyz world units per grid unit
    vec4 light;              // xyz towards the light, world space
    uvec3 dims;              // samples per axis
    uint triangle_capacity;  // compute path: triangles the frame's list holds
} params;
