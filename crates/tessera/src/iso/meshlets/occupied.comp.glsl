#version 460
// Occupied-block filtering (paper C §3.1, after PMB): the blocks whose min-max range holds the
// isovalue, compacted into a block list in any order (sorting meshlets by their block makes
// outputs comparable).
#include "iso/direct/block_list.glsl"
#include "iso/meshlets/params.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer Nodes { vec2 minmax_nodes[]; };
layout(binding = 1) buffer Blocks { BlockListHeader block_header; uint occupied_blocks[]; };

void main() {
    // Workgroups spread over x and y (tessera_gpu::spread_groups).
    uint block = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    uvec3 d = params.block_dims;
    if (block >= d.x * d.y * d.z) {
        return;
    }
    vec2 range = minmax_nodes[block];
    float iso = params.isovalue;
    if (range.x <= iso && iso <= range.y) {
        occupied_blocks[atomicAdd(block_header.count, 1u)] = block;
    }
}
