#version 460
// Lists the regions whose blocks may hold the isosurface at this frame's isovalue, and clears
// their visibility flags.
#include "iso/direct/params.glsl"
#include "iso/direct/cull.glsl"
#include "iso/direct/block_list.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer Nodes { vec2 minmax_nodes[]; };
layout(binding = 1) buffer Occupied { BlockListHeader occupied_list; uint occupied[]; };
layout(binding = 2) writeonly buffer Visible { uint visible[]; };

bool block_holds(uint block, float iso) {
    if (block == ~0u) {
        return false;
    }
    vec2 range = minmax_nodes[block];
    return iso >= range.x && iso <= range.y;
}

void main() {
    // Workgroups spread over x and y (tessera_gpu::spread_groups).
    uint region = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    uvec3 dims = params.dims.xyz;
    if (region >= cull_region_count(dims)) {
        return;
    }
    visible[region] = 0u;
    float iso = params.isovalue;
    if (block_holds(cull_region_block(region, 0u, dims), iso)
            || block_holds(cull_region_block(region, 1u, dims), iso)) {
        occupied[atomicAdd(occupied_list.count, 1u)] = region;
    }
}
