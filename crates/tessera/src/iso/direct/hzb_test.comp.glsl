#version 460
// The occlusion test of the compute path's culling, one invocation per block: counts the
// blocks whose (min, max) holds the isovalue and, of those not drawn in the first pass, lists
// the ones that may be visible for the second pass. A block may be visible when its cell box
// reaches the near plane, or when over the pixels its box could cover (a pixel's margin) the
// max-depth pyramid of the first pass holds a depth at or behind the box's nearest point.
#include "iso/direct/hzb.glsl"
#include "iso/direct/block_list.glsl"

layout(local_size_x = 256) in;
layout(binding = 0) readonly buffer Nodes { vec2 minmax_nodes[]; };
// Bit 1: the block was drawn in the first pass (it was seen last frame).
layout(binding = 1) readonly buffer BlockFlags { uint block_flags[]; };
layout(binding = 2) readonly buffer Hzb { float hzb[]; };
layout(binding = 3) buffer NewBlocks { BlockListHeader new_list; uint new_blocks[]; };
// [0] occupied blocks
layout(binding = 4) buffer Stats { uint stats[]; };

layout(push_constant) uniform HzbTestParams {
    mat4 grid_to_clip;
    uvec4 dims;   // xyz samples per axis, w pyramid levels
    uvec4 size;   // xy frame width and height
    vec4 iso;     // x the isovalue
} params;

// Slack for rounding: the rasterizer's depths come from the same matrix but other points
// (vertices on cell edges) and are interpolated in screen space.
const float DEPTH_SLACK = 1e-5;
// Texels per axis read at most: the level is the finest where the rectangle spans this many
// (8 instead of 4 culled ~9 % more of pass B's blocks at 4K on the 1024³ head, but cost as much
// time in this pass as it saved).
const int FOOTPRINT = 4;
// Pixels whose centres lie within this many pixels of the box's projected rectangle are tested.
// The rasterizer moves corners by at most 1/512 pixel when it snaps them, so a quarter pixel
// would do (on the 1024³ head it cut pass B by 4-11 %, the frame by 1-2.5 %); a whole pixel keeps
// a wide margin.
const float RECT_SLACK = 1.0;

bool may_be_visible(uvec3 block) {
    uvec3 dims = params.dims.xyz;
    uvec3 lo = block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    uvec3 hi = min(lo + uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z), dims - 1u);
    vec2 lo_ndc = vec2(1e30);
    vec2 hi_ndc = vec2(-1e30);
    float near_depth = 1e30;
    for (uint c = 0u; c < 8u; ++c) {
        vec3 p = mix(vec3(lo), vec3(hi), vec3(c & 1u, (c >> 1) & 1u, c >> 2));
        vec4 clip = params.grid_to_clip * vec4(p, 1.0);
        if (clip.w <= 1e-6 || clip.z < 0.0) {
            return true;  // reaches the near plane or behind the eye
        }
        vec3 ndc = clip.xyz / clip.w;
        lo_ndc = min(lo_ndc, ndc.xy);
        hi_ndc = max(hi_ndc, ndc.xy);
        near_depth = min(near_depth, ndc.z);
    }
    // Pixels whose centres (x + 1/2) the box's projection could reach, with slack.
    vec2 size = vec2(params.size.xy);
    vec2 first_f = clamp(ceil((lo_ndc * 0.5 + 0.5) * size - 0.5 - RECT_SLACK), vec2(-1.0), size);
    vec2 last_f = clamp(floor((hi_ndc * 0.5 + 0.5) * size - 0.5 + RECT_SLACK), vec2(-1.0), size);
    if (any(lessThan(last_f, vec2(0.0))) || any(greaterThanEqual(first_f, size))) {
        return false;  // off screen
    }
    ivec2 first = ivec2(max(first_f, vec2(0.0)));
    ivec2 last = ivec2(min(last_f, size - 1.0));
    uint levels = params.dims.w;
    uint level = 0u;
    ivec2 t0 = first >> 1;
    ivec2 t1 = last >> 1;
    while (any(greaterThanEqual(t1 - t0, ivec2(FOOTPRINT))) && level + 1u < levels) {
        level += 1u;
        t0 = first >> int(level + 1u);
        t1 = last >> int(level + 1u);
    }
    uvec2 dims2 = hzb_level_dims(params.size.xy, level);
    uint offset = hzb_level_offset(params.size.xy, level);
    float far_depth = 0.0;
    for (int y = t0.y; y <= t1.y; ++y) {
        for (int x = t0.x; x <= t1.x; ++x) {
            far_depth = max(far_depth, hzb[offset + uint(y) * dims2.x + uint(x)]);
        }
    }
    return far_depth >= near_depth - DEPTH_SLACK;
}

shared uint group_occupied;
shared uint group_new;
shared uint group_base;

void main() {
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        group_occupied = 0u;
        group_new = 0u;
    }
    barrier();
    uvec3 dims = params.dims.xyz;
    uvec3 block_dims = (dims - 2u) / uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + 1u;
    uint b = FLAT_INVOCATION;
    bool listed = false;
    uint slot = 0u;
    if (b < block_dims.x * block_dims.y * block_dims.z) {
        vec2 range = minmax_nodes[b];
        float iso = params.iso.x;
        if (iso >= range.x && iso <= range.y) {
            atomicAdd(group_occupied, 1u);
            uvec3 block = uvec3(b % block_dims.x, (b / block_dims.x) % block_dims.y,
                                b / (block_dims.x * block_dims.y));
            if ((block_flags[b] & 2u) == 0u && may_be_visible(block)) {
                listed = true;
                slot = atomicAdd(group_new, 1u);
            }
        }
    }
    barrier();
    if (me == 0u) {
        if (group_occupied > 0u) {
            atomicAdd(stats[0], group_occupied);
        }
        group_base = group_new > 0u ? atomicAdd(new_list.count, group_new) : 0u;
    }
    barrier();
    if (listed) {
        new_blocks[group_base + slot] = b;
    }
}
