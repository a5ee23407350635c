#version 460
// Levels 0 and 1 of the min-max octree at once: one workgroup per level-1 node, that is per
// 2×2×2 blocks of BLOCK_X×BLOCK_Y×BLOCK_Z cells. The group's samples, 2·BLOCK + 1 per axis, are
// read once into shared memory (a workgroup per block reads the faces it shares with its
// neighbours again, and does too little per invocation to hide the reads), then 32
// invocations reduce each block through a shared-memory tree and one merges the blocks into
// their parent, so the level passes start at level 2. No subgroup size is assumed.
#include "common/volume.glsl"

layout(local_size_x = 256) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) writeonly buffer Nodes { vec2 minmax_nodes[]; };

layout(push_constant) uniform GroupParams {
    uvec4 volume_dims;  // xyz samples per axis
    uvec4 block_dims;   // xyz blocks per axis (level 0)
    uvec4 parent_dims;  // xyz level-1 nodes per axis, w: the first one's index (0: no level 1)
} params;

const uvec3 BLOCK = uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
const uvec3 SPAN = 2u * BLOCK + 1u;
const uvec3 BLOCK_SPAN = BLOCK + 1u;
const uint BLOCK_SAMPLES = BLOCK_SPAN.x * BLOCK_SPAN.y * BLOCK_SPAN.z;
const uint LANES = 32u;  // invocations per block
shared float s_values[SPAN.x * SPAN.y * SPAN.z];
shared vec2 s_partial[256];

vec2 merge(vec2 a, vec2 b) {
    return vec2(min(a.x, b.x), max(a.y, b.y));
}

void main() {
    uint me = gl_LocalInvocationIndex;
    uvec3 origin = gl_WorkGroupID * 2u * BLOCK;
    for (uint i = me; i < SPAN.x * SPAN.y * SPAN.z; i += 256u) {
        uvec3 p = origin + uvec3(i % SPAN.x, (i / SPAN.x) % SPAN.y, i / (SPAN.x * SPAN.y));
        // Samples past the volume are never read below.
        s_values[i] = all(lessThan(p, params.volume_dims.xyz)) ? volume_texel(volume_tex, ivec3(p)) : 0.0;
    }
    barrier();

    uint b = me / LANES;
    uint lane = me % LANES;
    uvec3 corner = uvec3(b & 1u, (b >> 1) & 1u, b >> 2) * BLOCK;
    vec2 range = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
    for (uint j = lane; j < BLOCK_SAMPLES; j += LANES) {
        uvec3 local = corner + uvec3(j % BLOCK_SPAN.x, (j / BLOCK_SPAN.x) % BLOCK_SPAN.y,
                                     j / (BLOCK_SPAN.x * BLOCK_SPAN.y));
        if (all(lessThan(origin + local, params.volume_dims.xyz))) {
            range = merge(range, vec2(s_values[(local.z * SPAN.y + local.y) * SPAN.x + local.x]));
        }
    }
    s_partial[me] = range;
    barrier();
    for (uint stride = LANES / 2u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            s_partial[me] = merge(s_partial[me], s_partial[me + stride]);
        }
        barrier();
    }
    // Blocks past the last one hold samples of the last plane only: not nodes, not merged.
    uvec3 block = gl_WorkGroupID * 2u + uvec3(b & 1u, (b >> 1) & 1u, b >> 2);
    bool exists = all(lessThan(block, params.block_dims.xyz));
    if (lane == 0u && exists) {
        minmax_nodes[block.x + params.block_dims.x * (block.y + params.block_dims.y * block.z)] =
            s_partial[me];
    }
    if (me == 0u && params.parent_dims.w != 0u) {
        vec2 parent = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
        for (uint c = 0u; c < 8u; ++c) {
            uvec3 child = gl_WorkGroupID * 2u + uvec3(c & 1u, (c >> 1) & 1u, c >> 2);
            if (all(lessThan(child, params.block_dims.xyz))) {
                parent = merge(parent, s_partial[c * LANES]);
            }
        }
        uvec3 node = gl_WorkGroupID;
        minmax_nodes[params.parent_dims.w + node.x + params.parent_dims.x * (node.y + params.parent_dims.y * node.z)] =
            parent;
    }
}
