// The compute rasterizer's drawing of one clip-space triangle, following the CPU reference
// `tessera_data::rasterize` rule for rule. Clip in homogeneous space (Sutherland-Hodgman,
// w > MIN_W, near z >= 0, far z <= w, guard band |x|, |y| <= GUARD_BAND w), map the polygon to the
// viewport with positions snapped to 1/SUBPIXEL pixel, draw it as a fan. Coverage is decided
// exactly: integer edge functions on the snapped grid with the top-left rule, sampled at pixel
// centres. Depth is NDC z interpolated linearly in screen space; the visible fragment per pixel
// is kept with a 64-bit atomicMin on (depth bits << 32 | triangle index), which equals the
// reference's LESS test in list order (equal depths keep the lower index). Triangles of one
// winding may be left out, as the reference's rasterize_clip_triangles_hiding does.
//
// Used by the raster pass (raster.comp.glsl) and by passes that draw the triangles they make
// themselves. The includer declares the frame's buffers by these names:
//   buffer ... { uint64_t depth_payload[]; };   // the frame (raster/mod.rs)
//   writeonly buffer ... { uint tile_frames[]; };  // per RASTER_TILE tile, the last frame number
// enables GL_EXT_shader_explicit_arithmetic_types_int64, GL_EXT_shader_atomic_int64 and
// GL_KHR_memory_scope_semantics (before any code), and defines SUBPIXEL_BITS, MIN_W, GUARD_BAND and RASTER_TILE
// (raster::raster_defines).

#ifndef RASTER_RASTER_DRAW_GLSL
#define RASTER_RASTER_DRAW_GLSL

#include "common/exact.glsl"
#include "raster/raster.glsl"

// The rasterizer's variant (raster::RasterVariant): 0 exact; 1 exact, each fragment's atomic
// left out where the frame already holds a nearer value; for measuring where the time goes,
// 2 fragments computed but not written, 3 triangles set up and their tiles marked, no pixels,
// 4 no triangle read or drawn (the callers leave out their loads too).
#ifndef RASTER_VARIANT
#define RASTER_VARIANT 0
#endif
// 1: raster_draw_triangle_in_subgroup lets a subgroup walk its large triangles together
// (raster::RasterVariant::SubgroupWalk); the includer then enables
// GL_KHR_shader_subgroup_ballot and GL_KHR_shader_subgroup_shuffle.
#ifndef RASTER_SUBGROUP_WALK
#define RASTER_SUBGROUP_WALK 0
#endif

// What a raster pass draws into, and how (RasterParams on the host).
struct RasterPass {
    uvec2 size;          // frame width, height in pixels
    uint frame_number;   // marked into every tile a triangle's pixel box reaches
    // 1: triangles of positive area on the snapped grid draw nothing; -1: those of negative
    // area; 0: both sides draw (tessera_data::rasterize::ScreenWinding, tessera_data::facing).
    int hidden_winding;
};

const int SUBPIXEL = 1 << SUBPIXEL_BITS;
const int HALF_SUBPIXEL = SUBPIXEL / 2;
const int PLANES = 7;
// Each plane adds at most one corner to a convex polygon; the slack absorbs rounding.
const int MAX_CORNERS = 12;

// Signed distance to clip plane `plane`, inside where >= 0 (the reference's order).
float plane_distance(int plane, vec4 c) {
    switch (plane) {
    case 0: return c.w - MIN_W;
    case 1: return c.z;
    case 2: return c.w - c.z;
    case 3: return GUARD_BAND * c.w - c.x;
    case 4: return GUARD_BAND * c.w + c.x;
    case 5: return GUARD_BAND * c.w - c.y;
    default: return GUARD_BAND * c.w + c.y;
    }
}

// Bit p set where the corner is not inside plane p (NaN counts as outside, as in the reference).
uint outside_mask(vec4 c) {
    uint mask = 0u;
    for (int p = 0; p < PLANES; ++p) {
        mask |= (plane_distance(p, c) >= 0.0) ? 0u : (1u << p);
    }
    return mask;
}

bool lexically_before_or_equal(vec4 a, vec4 b) {
    for (int i = 0; i < 4; ++i) {
        if (a[i] != b[i]) {
            return a[i] < b[i];
        }
    }
    return true;
}

// Where edge a-b crosses a plane. Computed from the lexically smaller end, so triangles sharing
// an edge get bit-identical new corners and stay watertight.
vec4 intersect(vec4 a, float da, vec4 b, float db) {
    return lexically_before_or_equal(a, b) ? mix(a, b, da / (da - db)) : mix(b, a, db / (db - da));
}

// round(s * (x / w + 1)) with halves away from zero, as if computed exactly: a double-float
// evaluation (~2^-44 relative), so the snapped grid point agrees with the reference's f64 one
// except within ~1e-6 sub-pixel of a rounding tie. Plain f32 put ~0.1% of corners on a
// neighbouring grid point in a 256-pixel frame (measured), and more the larger the frame.
int snap(float x, float w, float s) {
    precise float q = x / w;
    precise float qw = q * w;
    precise float rest = (x - qw) - product_error(q, w, qw);  // x - q w, x - qw being exact
    precise float q_rest = rest / w;                           // x / w = q + q_rest
    precise float p = q * s;
    precise float p_err = product_error(q, s, p);             // q s = p + p_err
    precise float t = p + s;                                   // two-sum: p + s = t + t_err
    precise float b = t - p;
    precise float t_err = (p - (t - b)) + (s - b);
    precise float tail = t_err + p_err + q_rest * s;
    precise float n = roundEven(t);  // |t| < 2^24, so n and t - n are exact
    precise float f = (t - n) + tail + 0.5;  // value - n + 1/2
    precise float k = floor(f);
    if (f == k && t < 0.0) {
        k -= 1.0;  // an exact half below zero rounds away from zero
    }
    return int(n) + int(k);
}

// A corner on screen: position in 1/SUBPIXEL pixels, NDC depth.
struct Corner {
    ivec2 p;
    float z;
};

Corner to_screen(uvec2 size, vec4 c) {
    vec2 s = vec2(size) * float(HALF_SUBPIXEL);
    return Corner(ivec2(snap(c.x, c.w, s.x), snap(c.y, c.w, s.y)), c.z / c.w);
}

// Twice the signed area of (a, b, p) on the snapped grid; positive when p lies to the right of
// a->b on screen (x right, y down). Exact: |coordinates| < 2^24.
int64_t edge(ivec2 a, ivec2 b, ivec2 p) {
    return int64_t(b.x - a.x) * int64_t(p.y - a.y) - int64_t(b.y - a.y) * int64_t(p.x - a.x);
}

// Top-left rule for edge a->b of a triangle with positive area: a top edge is horizontal and
// runs right, a left edge runs up. Pixel centres exactly on other edges stay out.
int64_t edge_bias(ivec2 a, ivec2 b) {
    ivec2 d = b - a;
    return (d.y < 0 || (d.y == 0 && d.x > 0)) ? int64_t(0) : int64_t(1);
}

// A triangle of positive area on the snapped grid, ready to walk: what each way of walking
// its pixels needs.
struct FanSetup {
    ivec2 first;      // its pixel box, inside the viewport
    ivec2 last;
    // Edge i is opposite corner i; its function is corner i's unnormalized weight. `row`
    // holds them at the centre of pixel `first`, less `bias` (the top-left rule), so that a
    // pixel is inside where all three are >= 0.
    i64vec3 row;
    i64vec3 bias;
    i64vec3 step_x;   // per pixel right
    i64vec3 step_y;   // per pixel down
    float z0;         // NDC depth of corner a
    vec2 dz;          // corners b's and c's depths relative to a's
    float inv_area;
    // Its corners' box spans under 2^15 sub-pixels a side, so every edge function at a pixel
    // centre in the box is below 2^31 in magnitude (|e| <= 2 W H): a 32-bit walk is exact.
    bool fits_32_bits;
};

// Sets up fan triangle (a, b, c) for walking and marks the tiles its pixel box reaches; false
// where it draws nothing (zero area, a hidden winding, no pixel centre inside the viewport).
bool fan_setup(RasterPass pass, Corner a, Corner b, Corner c, out FanSetup s) {
    int64_t area = edge(a.p, b.p, c.p);
    if (area == 0) {
        return false;  // zero area: no fragments
    }
    if (pass.hidden_winding != 0 && (area > 0) == (pass.hidden_winding > 0)) {
        return false;  // turned away from every view ray's first surface
    }
    if (area < 0) {  // double-sided: turn it around
        Corner t = b;
        b = c;
        c = t;
        area = -area;
    }
    ivec2 lo = min(a.p, min(b.p, c.p));
    ivec2 hi = max(a.p, max(b.p, c.p));
    // Pixels whose centre (x + 1/2) lies in [lo, hi], inside the viewport.
    s.first = max((lo + (HALF_SUBPIXEL - 1)) >> SUBPIXEL_BITS, ivec2(0));
    s.last = min((hi - HALF_SUBPIXEL) >> SUBPIXEL_BITS, ivec2(pass.size) - 1);
    if (any(greaterThan(s.first, s.last))) {
        return false;
    }
    // Every tile the pixel box reaches: a superset of the tiles the triangle draws into, which
    // a resolve that reads only marked tiles must all see. Every writer stores the same value.
    uint tiles_per_row = raster_tiles_per_row(pass.size.x);
    uvec2 first_tile = uvec2(s.first) / RASTER_TILE;
    uvec2 last_tile = uvec2(s.last) / RASTER_TILE;
    for (uint ty = first_tile.y; ty <= last_tile.y; ++ty) {
        for (uint tx = first_tile.x; tx <= last_tile.x; ++tx) {
            tile_frames[ty * tiles_per_row + tx] = pass.frame_number;
        }
    }
    ivec2 centre = s.first * SUBPIXEL + HALF_SUBPIXEL;
    s.bias = i64vec3(edge_bias(b.p, c.p), edge_bias(c.p, a.p), edge_bias(a.p, b.p));
    s.row = i64vec3(edge(b.p, c.p, centre), edge(c.p, a.p, centre), edge(a.p, b.p, centre)) - s.bias;
    s.step_x = -i64vec3(c.p.y - b.p.y, a.p.y - c.p.y, b.p.y - a.p.y) * SUBPIXEL;
    s.step_y = i64vec3(c.p.x - b.p.x, a.p.x - c.p.x, b.p.x - a.p.x) * SUBPIXEL;
    // Depth relative to corner a: exact where the triangle has one depth.
    s.z0 = a.z;
    s.dz = vec2(b.z - a.z, c.z - a.z);
    s.inv_area = 1.0 / float(area);
    s.fits_32_bits = all(lessThan(hi - lo, ivec2(1 << 15)));
    return true;
}

// Pixel (x, y) of a set-up triangle, covered, with corners b's and c's weights `weights`.
// `precise` keeps the depth's arithmetic the same wherever this is inlined, so every way of
// walking a triangle gives it the same depths.
void draw_fragment(RasterPass pass, FanSetup s, int x, int y, vec2 weights, uint index) {
    precise float depth = s.z0 + weights.x * s.dz.x + weights.y * s.dz.y;
    depth = depth > 0.0 ? depth : 0.0;
    // The reference tests LESS against a buffer cleared to 1.0.
    if (depth < 1.0) {
        uint pixel = uint(y) * pass.size.x + uint(x);
        uint64_t value = packUint2x32(uvec2(index, floatBitsToUint(depth)));
#if RASTER_VARIANT == 1
        // Values only fall: one at or below ours already keeps ours out.
        uint64_t held = atomicLoad(depth_payload[pixel], gl_ScopeDevice,
                                   gl_StorageSemanticsNone, gl_SemanticsRelaxed);
        if (value < held) {
            atomicMin(depth_payload[pixel], value);
        }
#elif RASTER_VARIANT == 2
        if (index == 0xffffffffu) {  // never: keeps the fragment's arithmetic
            depth_payload[pixel] = value;
        }
#else
        atomicMin(depth_payload[pixel], value);
#endif
    }
}

// Walks a set-up triangle's pixel box row by row with this invocation alone.
void walk_alone(RasterPass pass, FanSetup s, uint index) {
#if RASTER_VARIANT == 3
    return;
#endif
    i64vec3 row = s.row;
    for (int y = s.first.y; y <= s.last.y; ++y) {
        i64vec3 e = row;
        for (int x = s.first.x; x <= s.last.x; ++x) {
            if ((e.x | e.y | e.z) >= 0) {
                draw_fragment(pass, s, x, y, vec2(e.yz + s.bias.yz) * s.inv_area, index);
            }
            e += s.step_x;
        }
        row += s.step_y;
    }
}

void draw_fan_triangle(RasterPass pass, Corner a, Corner b, Corner c, uint index) {
    FanSetup s;
    if (fan_setup(pass, a, b, c, s)) {
        walk_alone(pass, s, index);
    }
}

// Draws the triangle with clip-space corners c0, c1, c2 into the frame as `payload` (its index
// in the frame): clipped plane by plane as the reference does, then drawn as a fan.
void raster_draw_triangle(RasterPass pass, vec4 c0, vec4 c1, vec4 c2, uint payload) {
#if RASTER_VARIANT == 4
    return;
#endif
    uint m0 = outside_mask(c0), m1 = outside_mask(c1), m2 = outside_mask(c2);
    if ((m0 & m1 & m2) != 0u) {
        return;  // wholly outside one plane
    }
    if ((m0 | m1 | m2) == 0u) {  // the common case
        draw_fan_triangle(pass, to_screen(pass.size, c0), to_screen(pass.size, c1),
                          to_screen(pass.size, c2), payload);
        return;
    }
    vec4 polygon[MAX_CORNERS];
    vec4 clipped[MAX_CORNERS];
    polygon[0] = c0;
    polygon[1] = c1;
    polygon[2] = c2;
    int n = 3;
    for (int plane = 0; plane < PLANES; ++plane) {
        int inside = 0;
        for (int i = 0; i < n; ++i) {
            inside += plane_distance(plane, polygon[i]) >= 0.0 ? 1 : 0;
        }
        if (inside == n) {
            continue;
        }
        if (inside == 0) {
            return;
        }
        int m = 0;
        for (int i = 0; i < n; ++i) {
            vec4 a = polygon[i];
            vec4 b = polygon[i + 1 < n ? i + 1 : 0];
            float da = plane_distance(plane, a);
            float db = plane_distance(plane, b);
            if (da >= 0.0 && m < MAX_CORNERS) {
                clipped[m++] = a;
            }
            if ((da >= 0.0) != (db >= 0.0) && m < MAX_CORNERS) {
                clipped[m++] = intersect(a, da, b, db);
            }
        }
        n = m;
        for (int i = 0; i < n; ++i) {
            polygon[i] = clipped[i];
        }
        if (n < 3) {
            return;
        }
    }
    Corner first = to_screen(pass.size, polygon[0]);
    Corner previous = to_screen(pass.size, polygon[1]);
    for (int k = 2; k < n; ++k) {
        Corner next = to_screen(pass.size, polygon[k]);
        draw_fan_triangle(pass, first, previous, next, payload);
        previous = next;
    }
}

#if RASTER_SUBGROUP_WALK
#include "common/subgroup_turns.glsl"

// Walks, with the whole subgroup, the set-up triangles of the invocations where `grouped`
// holds, one after another: invocation k takes the box's pixels k, k + lanes, ... in row
// order, so neighbouring invocations draw neighbouring pixels (their atomics meet a few
// memory sectors) and a large box is spread over the subgroup rather than left to one
// invocation. Each grouped triangle must fit the 32-bit walk (FanSetup::fits_32_bits): its
// edge functions are then the exact integers the 64-bit walk computes. Call from uniform
// control flow.
void walk_subgroup(RasterPass pass, bool grouped, FanSetup s, uint index) {
    uint me = gl_SubgroupInvocationID;
    uint lanes = gl_SubgroupSize;
    // Unset where not grouped: such lanes' values are never read.
    ivec3 row = ivec3(s.row);
    ivec3 step_x = ivec3(s.step_x);
    ivec3 step_y = ivec3(s.step_y);
    uvec4 pending = subgroupBallot(grouped);
    while (subgroup_turns_left(pending)) {
        uint lane = subgroup_next_turn(pending);
        FanSetup t;
        t.first = subgroupShuffle(s.first, lane);
        t.last = subgroupShuffle(s.last, lane);
        t.bias = i64vec3(subgroupShuffle(ivec3(s.bias), lane));
        t.z0 = subgroupShuffle(s.z0, lane);
        t.dz = subgroupShuffle(s.dz, lane);
        t.inv_area = subgroupShuffle(s.inv_area, lane);
        ivec3 origin = subgroupShuffle(row, lane);
        ivec3 right = subgroupShuffle(step_x, lane);
        ivec3 down = subgroupShuffle(step_y, lane);
        uint drawn = subgroupShuffle(index, lane);
        uint width = uint(t.last.x - t.first.x + 1);
        uint pixels = width * uint(t.last.y - t.first.y + 1);
        // This invocation's pixel, relative to the box, advanced by `lanes` pixels a step.
        uint x = me % width;
        uint y = me / width;
        uint lanes_x = lanes % width;
        uint lanes_y = lanes / width;
        for (uint k = me; k < pixels; k += lanes) {
            ivec3 e = origin + int(x) * right + int(y) * down;
            if ((e.x | e.y | e.z) >= 0) {
                draw_fragment(pass, t, t.first.x + int(x), t.first.y + int(y),
                              vec2(e.yz + ivec2(t.bias.yz)) * t.inv_area, drawn);
            }
            x += lanes_x;
            y += lanes_y;
            if (x >= width) {
                x -= width;
                ++y;
            }
        }
    }
}

// raster_draw_triangle for a subgroup, from uniform control flow: an invocation with `valid`
// draws its triangle; those whose pixel box holds more than RASTER_SUBGROUP_WALK_ABOVE pixels
// (and fits the 32-bit walk) are walked by the whole subgroup after each invocation has drawn
// its smaller one alone. Triangles the clip planes cut are drawn alone. The frame is the one
// raster_draw_triangle draws.
void raster_draw_triangle_in_subgroup(RasterPass pass, bool valid, vec4 c0, vec4 c1, vec4 c2,
                                      uint payload) {
    FanSetup s;
    bool grouped = false;
#if RASTER_VARIANT != 4
    if (valid) {
        uint m0 = outside_mask(c0), m1 = outside_mask(c1), m2 = outside_mask(c2);
        if ((m0 | m1 | m2) == 0u) {
            if (fan_setup(pass, to_screen(pass.size, c0), to_screen(pass.size, c1),
                          to_screen(pass.size, c2), s)) {
                ivec2 extent = s.last - s.first + 1;
                grouped = s.fits_32_bits && extent.x * extent.y > RASTER_SUBGROUP_WALK_ABOVE;
                if (!grouped) {
                    walk_alone(pass, s, payload);
                }
            }
        } else {
            raster_draw_triangle(pass, c0, c1, c2, payload);
        }
    }
#endif
    walk_subgroup(pass, grouped, s, payload);
}
#endif

#endif
