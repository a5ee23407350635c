#version 460
// One PATCH SUBDIVISION step (paper E §4.1) with the rules of tessera_data::param::lod, one
// workgroup per patch: 64 invocations take the 32 u-line and 32 v-line samples, 25 of them the
// culling grid; 8 measure the lines; one decides. Shared memory, not subgroup operations, so
// that no subgroup size is assumed. `precise` keeps every operation the CPU rounds separately
// rounded separately here (no fused multiply-add), and the two operations Vulkan lets be
// inexact, division and sqrt, are corrected to the CPU's rounding (divide_by_7, rounded_sqrt),
// so equal positions give equal decisions, extents and child ranges on any device.
//
// PARAM_SPLIT_DECIDE (pattern for flags a | b << 1 | c << 2 | d << 3) and PARAM_SPLIT_PIECES
// (per pattern: child count << 16 | nibble i = u part | v part << 2; 0 lower, 1 upper, 2 whole)
// are generated from tessera_data's SplitPattern (param/lod.rs).
#define PARAM_STATE_BINDING 3
#include "common/exact.glsl"
#include "param/functions.glsl"
#include "param/view.glsl"
#include "param/patch.glsl"
#include "param/lod_params.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 64) in;
layout(binding = 4, std430) readonly buffer PatchesIn { Patch patches_in[]; };
layout(binding = 5, std430) writeonly buffer PatchesOut { Patch patches_out[]; };
layout(binding = 6, std430) writeonly buffer PatchesRender { Patch patches_render[]; };
// Debug capture: every sample's parameters and pixel position (x NaN behind the eye).
struct LodSample {
    uint object;
    float u;
    float v;
    float x;
    float y;
};
layout(binding = 7, std430) writeonly buffer Capture { LodSample captured[]; };

const uint SAMPLES = 89u;
const uint OUT_LEFT = 1u;
const uint OUT_RIGHT = 2u;
const uint OUT_TOP = 4u;
const uint OUT_BOTTOM = 8u;
const uint OUT_BEHIND = 16u;
const uint SPLIT_DECIDE[16] = PARAM_SPLIT_DECIDE;
const uint SPLIT_PIECES[8] = PARAM_SPLIT_PIECES;

shared vec2 s_pixel[SAMPLES];
shared bool s_front[SAMPLES];
shared uint s_outcode_and;
shared uint s_capture_base;
shared float s_extent[8];

uint outcode(bool front, vec2 p) {
    if (!front) {
        return OUT_BEHIND;
    }
    return (p.x < 0.0 ? OUT_LEFT : 0u) | (p.x > params.viewport.x ? OUT_RIGHT : 0u)
         | (p.y < 0.0 ? OUT_TOP : 0u) | (p.y > params.viewport.y ? OUT_BOTTOM : 0u);
}

// Projects sample `index` at (u, v), stores it and returns its outcode.
uint take_sample(uint index, uint object, float u, float v) {
    vec2 pixel;
    float depth;
    bool front = param_project(params.world_to_clip, params.viewport, param_world_position(object, u, v), pixel, depth);
    front = front && !any(isnan(pixel));
    s_pixel[index] = pixel;
    s_front[index] = front;
    uint slot = s_capture_base + index;
    if (slot < params.capture_capacity) {
        captured[slot] = LodSample(object, u, v, front ? pixel.x : uintBitsToFloat(0x7fc00000u), pixel.y);
    }
    return outcode(front, pixel);
}

// x / 7 correctly rounded, as the CPU computes it. Vulkan lets `/` be off by 2.5 ulp (NVIDIA's
// is), so the float nearest x / 7 is picked among the quotient's neighbours by the exact
// residual x - 7c (x - 7c is exact by Sterbenz's lemma, 7c's rounding error is added back; no
// quotient of x by 7 lies halfway between two floats, so there are no ties).
float divide_by_7(float x) {
    float q = x / 7.0;
    float best = q;
    float best_residual = uintBitsToFloat(0x7f800000u);
    for (int k = -3; k <= 3; ++k) {
        float c = uintBitsToFloat(uint(int(floatBitsToUint(q)) + k));
        precise float p = 7.0 * c;
        precise float residual = abs((x - p) - product_error(7.0, c, p));
        if (residual < best_residual) {
            best = c;
            best_residual = residual;
        }
    }
    return best;
}

// Sum of the 7 segment lengths of a line, endpoints clamped to the viewport; a segment with an
// end behind the eye counts 0.
float line_extent(uint first) {
    precise float sum = 0.0;
    for (uint i = first; i < first + 7u; ++i) {
        if (s_front[i] && s_front[i + 1u]) {
            vec2 a = min(max(s_pixel[i], vec2(0.0)), params.viewport);
            vec2 b = min(max(s_pixel[i + 1u], vec2(0.0)), params.viewport);
            precise float dx = b.x - a.x;
            precise float dy = b.y - a.y;
            precise float len = rounded_sqrt(dx * dx + dy * dy);
            sum = sum + len;
        }
    }
    return sum;
}

bool halvable(vec2 r) {
    precise float mid = r.x + (r.y - r.x) * 0.5;
    return r.x < mid && mid < r.y;
}

// Lower half (0), upper half (1) or all (2) of r.
vec2 part(vec2 r, uint which) {
    precise float mid = r.x + (r.y - r.x) * 0.5;
    return which == 0u ? vec2(r.x, mid) : (which == 1u ? vec2(mid, r.y) : r);
}

float pick(vec4 e, uint which) {
    return which == 0u ? max(e.x, e.y) : (which == 1u ? max(e.z, e.w) : max(max(e.x, e.y), max(e.z, e.w)));
}

// Appends `n` patches to the list of entry `entry`; returns the first slot. A next step's list
// (entry > 0) gets its dispatch arguments grown here, one workgroup per stored patch; the
// render list's are made by lod_prepare, which spreads a short list.
uint reserve(uint entry, uint n, uint capacity) {
    uint base = atomicAdd(entries[entry].count, n);
    uint stored = base >= capacity ? 0u : min(n, capacity - base);
    if (stored < n) {
        atomicAdd(dropped, n - stored);
    }
    if (entry > 0u && stored > 0u) {
        GROW_INDIRECT_ARGS(entries[entry].x, entries[entry].y, entries[entry].z, base + stored, 1u);
    }
    return base;
}

void main() {
    uint index = param_group_index();
    uint count = min(entries[1u + params.step].count, params.eval_capacity);
    if (index >= count) {
        return;  // uniform over the workgroup
    }
    Patch p = patches_in[index];
    uint lane = gl_LocalInvocationIndex;
    if (lane == 0u) {
        s_outcode_and = 0xffffffffu;
        s_capture_base = params.capture_capacity > 0u ? atomicAdd(capture_count, SAMPLES) : 0xffffffffu;
    }
    barrier();

    precise float du = p.u.y - p.u.x;
    precise float dv = p.v.y - p.v.x;
    float step_u = divide_by_7(du);
    float step_v = divide_by_7(dv);
    precise float quarter_u = du * 0.25;
    precise float quarter_v = dv * 0.25;
    uint k = (lane & 31u) >> 3;
    float across = float(k) + 0.5;
    float along = float(lane & 7u);
    precise float su = lane < 32u ? p.u.x + step_u * along : p.u.x + quarter_u * across;
    precise float sv = lane < 32u ? p.v.x + quarter_v * across : p.v.x + step_v * along;
    uint code = take_sample(lane, p.object, su, sv);
    if (lane < 25u) {
        precise float gu = p.u.x + quarter_u * float(lane % 5u);
        precise float gv = p.v.x + quarter_v * float(lane / 5u);
        code &= take_sample(64u + lane, p.object, min(max(gu, p.u.x), p.u.y), min(max(gv, p.v.x), p.v.y));
    }
    atomicAnd(s_outcode_and, code);
    barrier();
    if (lane < 8u) {
        s_extent[lane] = line_extent(lane * 8u);
    }
    barrier();
    if (lane != 0u) {
        return;
    }

    vec4 eu = vec4(s_extent[0], s_extent[1], s_extent[2], s_extent[3]);
    vec4 ev = vec4(s_extent[4], s_extent[5], s_extent[6], s_extent[7]);
    if (params.culling != 0u && s_outcode_and != 0u) {
        atomicAdd(culled, 1u);
        return;
    }
    bvec4 split_u = greaterThan(eu, vec4(params.thresholds.x));
    bvec4 split_v = greaterThan(ev, vec4(params.thresholds.y));
    bool requested = any(split_u) || any(split_v);
    // A range f32 cannot halve drops its own requests; the other direction then splits whole.
    bool halve_u_ok = halvable(p.u);
    if (!halve_u_ok) {
        split_u = bvec4(false);
        split_v = bvec4(any(split_v));
    }
    if (!halvable(p.v)) {
        split_v = bvec4(false);
        split_u = bvec4(any(split_u) && halve_u_ok);
    }
    uint flags = uint(split_u.x || split_u.y) | (uint(split_u.z || split_u.w) << 1)
               | (uint(split_v.x || split_v.y) << 2) | (uint(split_v.z || split_v.w) << 3);
    uint pattern = SPLIT_DECIDE[flags];
    uint pieces = SPLIT_PIECES[pattern];
    uint n = pieces >> 16;
    if (pattern == 0u) {
        uint slot = reserve(0u, 1u, params.render_capacity);
        if (slot < params.render_capacity) {
            vec2 extent = vec2(max(max(eu.x, eu.y), max(eu.z, eu.w)), max(max(ev.x, ev.y), max(ev.z, ev.w)));
            patches_render[slot] = Patch(p.u, p.v, extent, p.object, params.step | (requested ? PATCH_OVER_THRESHOLD : 0u));
        }
        if (requested) {
            atomicAdd(resolution_hits, 1u);
        }
        return;
    }
    bool last = params.last != 0u;
    uint base = last ? reserve(0u, n, params.render_capacity) : reserve(2u + params.step, n, params.eval_capacity);
    uint capacity = last ? params.render_capacity : params.eval_capacity;
    if (last) {
        atomicAdd(limit_hits, n);
    }
    for (uint i = 0u; i < n; ++i) {
        uint piece = (pieces >> (4u * i)) & 15u;
        uint pu = piece & 3u;
        uint pv = piece >> 2;
        // Extents of the child: the parent's maxima over the lines inside it, halved along a
        // halved direction (u-lines 0-1 lie in the lower v half; likewise v-lines).
        vec2 extent = vec2(pick(eu, pv) * (pu == 2u ? 1.0 : 0.5), pick(ev, pu) * (pv == 2u ? 1.0 : 0.5));
        Patch child = Patch(part(p.u, pu), part(p.v, pv), extent, p.object, params.step | (last ? PATCH_OVER_THRESHOLD : 0u));
        if (base + i < capacity) {
            if (last) {
                patches_render[base + i] = child;
            } else {
                patches_out[base + i] = child;
            }
        }
    }
}
