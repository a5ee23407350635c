#version 460
// End of a culled compute-path frame, one invocation per block: the blocks that own a pixel
// (bit 0 of their flags, set by the resolve) become next frame's first-pass list, and their
// flags become "drawn first" (bit 1) for next frame's occlusion test.
#include "raster/hzb.glsl"
#include "iso/direct/block_list.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 256) in;
layout(binding = 0) buffer BlockFlags { uint block_flags[]; };
// Next frame's pass-A list; its dispatch arguments (one workgroup per block) grow here.
layout(binding = 1) buffer NextBlocks { BlockListHeader next_list; uint next_blocks[]; };
// [2] blocks visible (owning a pixel)
layout(binding = 2) buffer Stats { uint stats[]; };

layout(push_constant) uniform CompactParams {
    uint block_count;
} params;

shared uint group_seen;
shared uint group_base;

void main() {
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        group_seen = 0u;
    }
    barrier();
    uint b = FLAT_INVOCATION;
    bool seen = false;
    uint slot = 0u;
    if (b < params.block_count) {
        uint flags = block_flags[b];
        seen = (flags & 1u) != 0u;
        uint next = seen ? 2u : 0u;
        if (flags != next) {
            block_flags[b] = next;
        }
        if (seen) {
            slot = atomicAdd(group_seen, 1u);
        }
    }
    barrier();
    if (me == 0u) {
        if (group_seen > 0u) {
            group_base = atomicAdd(next_list.count, group_seen);
            GROW_INDIRECT_ARGS3(next_list.args, group_base + group_seen, 1u);
            atomicAdd(stats[2], group_seen);
        }
    }
    barrier();
    if (seen) {
        next_blocks[group_base + slot] = b;
    }
}
