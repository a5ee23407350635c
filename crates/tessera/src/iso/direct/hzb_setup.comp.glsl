#version 460
// Bookkeeping of the compute path's culling, one invocation. A block list is its length, its
// indirect dispatch arguments (one workgroup per block, on a 2-D grid when a row would exceed
// the device's limit) and the linear block ids.
// Mode 0 (frame start): dispatch arguments for the first pass's list, the other lists emptied,
// the statistics restarted. Mode 1 (after the occlusion test): arguments for the second pass.
layout(local_size_x = 1) in;
#include "iso/direct/block_list.glsl"
layout(binding = 0) buffer FirstBlocks { BlockListHeader first_list; uint first_blocks[]; };
layout(binding = 1) buffer NewBlocks { BlockListHeader new_list; uint new_blocks[]; };
layout(binding = 2) buffer NextBlocks { BlockListHeader next_list; uint next_blocks[]; };
// [0] occupied blocks, [1] blocks drawn first, [2] blocks drawn second, [3] blocks seen
layout(binding = 3) buffer Stats { uint stats[4]; };

layout(push_constant) uniform SetupParams {
    uint mode;
    uint max_groups_x;  // the device's limit on workgroups along x
} setup;

uvec3 groups_for(uint n) {
    uint x = min(n, setup.max_groups_x);
    uint y = x == 0u ? 1u : (n + x - 1u) / x;
    return uvec3(x, y, 1u);
}

void main() {
    if (setup.mode == 0u) {
        uvec3 g = groups_for(first_list.count);
        first_list.args = uint[3](g.x, g.y, g.z);
        new_list = BlockListHeader(0u, uint[3](0u, 1u, 1u));
        next_list.count = 0u;
        stats = uint[4](0u, first_list.count, 0u, 0u);
    } else {
        uvec3 g = groups_for(new_list.count);
        new_list.args = uint[3](g.x, g.y, g.z);
        stats[2] = new_list.count;
    }
}
