// Push constants of the direct isosurface pipeline (host side: DirectParams).
layout(push_constant) uniform DirectParams {
    mat4 grid_to_clip;
    vec3 eye_world;
    float isovalue;
    vec4 grid_to_world;  // xyz world units per grid unit
    vec4 light;          // xyz towards the light, world space
    uvec3 dims;          // samples per axis
    // Triangles the mesh path's debug capture (0: off) or the compute path's list holds.
    uint triangle_capacity;
} params;
