#version 460
// Bookkeeping between culling passes, one invocation: mode 0 resets the lists of a frame
// (counts to zero, indirect y/z to one); mode 1 turns the occupied-region count into the
// proxy-quad draw's workgroup count; mode 2 turns the block counts into task-draw counts.
#include "iso/direct/block_list.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 1) in;
layout(binding = 0) buffer Occupied { BlockListHeader occupied_list; uint occupied[]; };
layout(binding = 1) buffer NewBlocks { BlockListHeader new_list; uint new_blocks[]; };
layout(binding = 2) buffer NextBlocks { BlockListHeader next_list; uint next_blocks[]; };
layout(push_constant) uniform SetupParams { uint mode; } setup;

const uint QUADS_PER_WORKGROUP = 32u;

void main() {
    if (setup.mode == 0u) {
        occupied_list = BlockListHeader(0u, uint[3](0u, 1u, 1u));
        new_list = BlockListHeader(0u, uint[3](0u, 1u, 1u));
        next_list = BlockListHeader(0u, uint[3](0u, 1u, 1u));
    } else if (setup.mode == 1u) {
        // Spread over x and y so no axis passes the 65,535 every device accepts.
        uint groups = max((occupied_list.count + QUADS_PER_WORKGROUP - 1u) / QUADS_PER_WORKGROUP, 1u);
        occupied_list.args[0] = min(groups, INDIRECT_MAX_GROUPS_X);
        occupied_list.args[1] = (groups + occupied_list.args[0] - 1u) / occupied_list.args[0];
    } else {
        new_list.args[0] = new_list.count;
        next_list.args[0] = next_list.count;
    }
}
