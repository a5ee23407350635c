// Push constants of shell traversal (host side: ShellParams).
layout(push_constant) uniform ShellParams {
    vec3 eye;             // pixel rays start here (world space)
    float near_depth;     // view-space depth where pixel rays begin
    vec3 forward;
    float tan_half_fov_x;
    vec3 right;
    float tan_half_fov_y;
    vec3 up;
    uint max_steps;       // per segment, before the loop guard ends it
    vec3 background;
    uint tet_count;
    vec2 scalar_range;    // (lo, hi) mapped onto [0, 1]
    uvec2 size;           // image width and height, or (rays, 1)
    uint vertex_count;
} params;
