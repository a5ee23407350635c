// The occlusion test against a max-depth pyramid (raster/hzb.glsl) of the shared compute
// rasterizer's frame: whether anything inside a box could be drawn in front of what the
// frame holds. Conservative: a box that fails is hidden behind the frame's pixels. Needs
// raster/hzb.glsl and a `float hzb[]` buffer holding the pyramid, declared before it.

#ifndef RASTER_HZB_TEST_GLSL
#define RASTER_HZB_TEST_GLSL

// Slack for rounding: the rasterizer's depths come from the same matrix but other points
// (vertices inside the box) and are interpolated in screen space.
const float HZB_DEPTH_SLACK = 1e-5;
// Texels per axis read at most: the level is the finest where the rectangle spans this many
// (8 instead of 4 culled ~9 % more of direct's second-pass blocks at 4K on the 1024³ head, but
// cost as much time in its test pass as it saved).
const int HZB_FOOTPRINT = 4;
// Pixels whose centres lie within this many pixels of the box's projected rectangle are tested.
// The rasterizer moves corners by at most 1/512 pixel when it snaps them, so a quarter pixel
// would do (on the 1024³ head it cut direct's second pass by 4-11 %, the frame by 1-2.5 %); a
// whole pixel keeps a wide margin.
const float HZB_RECT_SLACK = 1.0;

// Whether the box lo ..= hi (in the space `to_clip` maps to clip space) may be visible in a
// frame of `size` pixels whose pyramid has `levels` levels: true when it reaches the near
// plane or passes behind the eye, or when over the pixels its box could cover the pyramid
// holds a depth at or behind the box's nearest point.
bool hzb_box_may_be_visible(mat4 to_clip, vec3 lo, vec3 hi, uvec2 size, uint levels) {
    vec2 lo_ndc = vec2(1e30);
    vec2 hi_ndc = vec2(-1e30);
    float near_depth = 1e30;
    for (uint c = 0u; c < 8u; ++c) {
        vec3 p = mix(lo, hi, vec3(c & 1u, (c >> 1) & 1u, c >> 2));
        vec4 clip = to_clip * vec4(p, 1.0);
        if (clip.w <= 1e-6 || clip.z < 0.0) {
            return true;
        }
        vec3 ndc = clip.xyz / clip.w;
        lo_ndc = min(lo_ndc, ndc.xy);
        hi_ndc = max(hi_ndc, ndc.xy);
        near_depth = min(near_depth, ndc.z);
    }
    // Pixels whose centres (x + 1/2) the box's projection could reach, with slack.
    vec2 pixels = vec2(size);
    vec2 first_f = clamp(ceil((lo_ndc * 0.5 + 0.5) * pixels - 0.5 - HZB_RECT_SLACK), vec2(-1.0), pixels);
    vec2 last_f = clamp(floor((hi_ndc * 0.5 + 0.5) * pixels - 0.5 + HZB_RECT_SLACK), vec2(-1.0), pixels);
    if (any(lessThan(last_f, vec2(0.0))) || any(greaterThanEqual(first_f, pixels))) {
        return false;  // off screen
    }
    ivec2 first = ivec2(max(first_f, vec2(0.0)));
    ivec2 last = ivec2(min(last_f, pixels - 1.0));
    uint level = 0u;
    ivec2 t0 = first >> 1;
    ivec2 t1 = last >> 1;
    while (any(greaterThanEqual(t1 - t0, ivec2(HZB_FOOTPRINT))) && level + 1u < levels) {
        level += 1u;
        t0 = first >> int(level + 1u);
        t1 = last >> int(level + 1u);
    }
    uvec2 dims = hzb_level_dims(size, level);
    uint offset = hzb_level_offset(size, level);
    float far_depth = 0.0;
    for (int y = t0.y; y <= t1.y; ++y) {
        for (int x = t0.x; x <= t1.x; ++x) {
            far_depth = max(far_depth, hzb[offset + uint(y) * dims.x + uint(x)]);
        }
    }
    return far_depth >= near_depth - HZB_DEPTH_SLACK;
}

#endif
