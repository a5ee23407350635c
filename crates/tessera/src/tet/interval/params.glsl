// Push constants of interval shading (host side: IntervalParams).
layout(push_constant) uniform IntervalParams {
    mat4 world_to_clip;
    vec4 view;     // x tan(fov_x/2), y tan(fov_y/2), z unused, w near-plane view depth
    uvec4 counts;  // x tets, y width, z height, w compute path: pixels one invocation draws
    vec4 eye;      // xyz the eye in world space
    vec2 scalar_range; // (lo, hi) mapped onto [0, 1]
} params;
