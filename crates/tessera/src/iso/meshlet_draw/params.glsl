// Push constants of every meshlet draw pass (host side: iso::meshlet_draw::MeshletDrawParams).
layout(push_constant) uniform MeshletDrawParams {
    mat4 grid_to_clip;
    vec3 eye_world;
    uint bounds;             // MESHLET_BOUNDS_*: the box frustum culling tests
    vec3 grid_to_world;      // world units per grid unit
    uint frame_width;        // compute path: pixels of the frame (occlusion culling)
    vec3 light;              // towards the light, world space
    uint frame_height;
    uvec3 dims;              // samples per axis
    uint triangle_capacity;  // compute path: triangles the frame's list holds
} params;
