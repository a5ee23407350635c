// Push constants of the direct isosurface pipeline (host side: DirectParams).
layout(push_constant) uniform DirectParams {
    mat4 grid_to_clip;
    vec4 eye_world;      // w = isovalue
    vec4 grid_to_world;  // xyz world units per grid unit
    vec4 light;          // xyz towards the light, world space
    uvec4 dims;          // xyz samples per axis, w = triangle capture capacity (0: off)
} params;
