#version 460
// Level 0 of the min-max octree: one workgroup per block of BLOCK_X×BLOCK_Y×BLOCK_Z cells, one
// invocation per cell, reduced in shared memory (no subgroup size is assumed).
#include "common/volume.glsl"

layout(local_size_x = BLOCK_X, local_size_y = BLOCK_Y, local_size_z = BLOCK_Z) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) writeonly buffer Nodes { vec2 minmax_nodes[]; };

layout(push_constant) uniform BlockParams {
    uvec4 volume_dims;  // xyz samples per axis
    uvec4 block_dims;   // xyz blocks per axis
} params;

const uint CELLS = BLOCK_X * BLOCK_Y * BLOCK_Z;
shared vec2 partial[CELLS];

void main() {
    uvec3 cell = gl_WorkGroupID * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + gl_LocalInvocationID;
    vec2 range = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
    if (all(lessThan(cell, params.volume_dims.xyz - 1u))) {
        for (int c = 0; c < 8; ++c) {
            ivec3 p = ivec3(cell) + ivec3(c & 1, (c >> 1) & 1, c >> 2);
            float v = volume_texel(volume_tex, p);
            range = vec2(min(range.x, v), max(range.y, v));
        }
    }
    uint me = gl_LocalInvocationIndex;
    partial[me] = range;
    barrier();
    for (uint stride = CELLS / 2; stride > 0; stride /= 2) {
        if (me < stride) {
            vec2 other = partial[me + stride];
            partial[me] = vec2(min(partial[me].x, other.x), max(partial[me].y, other.y));
        }
        barrier();
    }
    if (me == 0) {
        uvec3 b = gl_WorkGroupID;
        minmax_nodes[b.x + params.block_dims.x * (b.y + params.block_dims.y * b.z)] = partial[0];
    }
}
