#version 460
// After the visibility test: the visible regions' blocks become next frame's occluder list,
// those not drawn as occluders this frame go to this frame's second pass, and the flags are
// kept as next frame's "drawn first" set.
#include "iso/direct/params.glsl"
#include "iso/direct/cull.glsl"
#include "iso/direct/block_list.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer Visible { uint visible[]; };
layout(binding = 1) buffer Previous { uint previous[]; };
layout(binding = 2) buffer NewBlocks { BlockListHeader new_list; uint new_blocks[]; };
layout(binding = 3) buffer NextBlocks { BlockListHeader next_list; uint next_blocks[]; };

void main() {
    // Workgroups spread over x and y (tessera_gpu::spread_groups).
    uint region = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    uvec3 dims = params.dims.xyz;
    if (region >= cull_region_count(dims)) {
        return;
    }
    uint seen = visible[region];
    uint drawn_first = previous[region];
    previous[region] = seen;
    if (seen == 0u) {
        return;
    }
    for (uint h = 0u; h < 2u; ++h) {
        uint block = cull_region_block(region, h, dims);
        if (block == ~0u) {
            continue;
        }
        next_blocks[atomicAdd(next_list.count, 1u)] = block;
        if (drawn_first == 0u) {
            new_blocks[atomicAdd(new_list.count, 1u)] = block;
        }
    }
}
