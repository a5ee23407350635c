// Push constants of interval shading (host side: IntervalParams).
layout(push_constant) uniform IntervalParams {
    mat4 world_to_clip;
    vec2 tan_half_fov;  // tan(fov_x / 2), tan(fov_y / 2)
    float near_depth;   // view-space depth of the near plane
    float pad0;
    uvec4 counts;  // x tets, y width, z height, w compute path: pixels one invocation draws
    vec4 eye;      // xyz the eye in world space
    vec2 scalar_range; // (lo, hi) mapped onto [0, 1]
} params;
