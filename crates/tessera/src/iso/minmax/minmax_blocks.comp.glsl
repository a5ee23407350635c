#version 460
// Level 0 of the min-max octree: one workgroup per block of BLOCK_X×BLOCK_Y×BLOCK_Z cells.
// The block's cells touch (BLOCK+1)^3 samples; each invocation fetches at most two of them (not
// the 8 corners of "its" cell, which would read every sample up to 8 times), then the workgroup
// reduces: with subgroup arithmetic, per subgroup and then across the subgroups through shared
// memory; without it, a shared-memory tree. No subgroup size is assumed.
#include "common/volume.glsl"
#if SUBGROUP_ARITHMETIC
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif

layout(local_size_x = BLOCK_X, local_size_y = BLOCK_Y, local_size_z = BLOCK_Z) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) writeonly buffer Nodes { vec2 minmax_nodes[]; };

layout(push_constant) uniform BlockParams {
    uvec4 volume_dims;  // xyz samples per axis
    uvec4 block_dims;   // xyz blocks per axis
} params;

const uint CELLS = BLOCK_X * BLOCK_Y * BLOCK_Z;
const uvec3 SPAN = uvec3(BLOCK_X + 1u, BLOCK_Y + 1u, BLOCK_Z + 1u);
const uint SAMPLES = SPAN.x * SPAN.y * SPAN.z;
shared vec2 partial[CELLS];

vec2 merge(vec2 a, vec2 b) {
    return vec2(min(a.x, b.x), max(a.y, b.y));
}

void main() {
    uvec3 origin = gl_WorkGroupID * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    uint me = gl_LocalInvocationIndex;
    vec2 range = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
    for (uint i = me; i < SAMPLES; i += CELLS) {
        uvec3 p = origin + uvec3(i % SPAN.x, (i / SPAN.x) % SPAN.y, i / (SPAN.x * SPAN.y));
        if (all(lessThan(p, params.volume_dims.xyz))) {
            float v = volume_texel(volume_tex, ivec3(p));
            range = merge(range, vec2(v));
        }
    }
#if SUBGROUP_ARITHMETIC
    range = vec2(subgroupMin(range.x), subgroupMax(range.y));
    if (subgroupElect()) {
        partial[gl_SubgroupID] = range;
    }
    barrier();
    if (me == 0) {
        for (uint s = 1; s < gl_NumSubgroups; ++s) {
            range = merge(range, partial[s]);
        }
        range = merge(range, partial[0]);
#else
    partial[me] = range;
    barrier();
    for (uint stride = CELLS / 2; stride > 0; stride /= 2) {
        if (me < stride) {
            partial[me] = merge(partial[me], partial[me + stride]);
        }
        barrier();
    }
    if (me == 0) {
        range = partial[0];
#endif
        uvec3 b = gl_WorkGroupID;
        minmax_nodes[b.x + params.block_dims.x * (b.y + params.block_dims.y * b.z)] = range;
    }
}
