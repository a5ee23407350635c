#version 460
// Occupied-block filtering of PMB: the blocks whose samples may hold the isovalue, compacted
// into a block list in any order.
//
// A block's range comes from level 0 of the min-max octree every prepared volume already has,
// not from a min-max volume per block size: every PMB size is a divisor (4×4×4, 8×4×4) or a
// multiple (8×8×8) of the octree's 8×8×4 blocks and aligned to them, so a PMB block overlaps
// one or two of them. Their union covers its samples, exactly when it is a multiple and
// conservatively when it is a divisor; a block taken too eagerly finds no crossed cell and
// writes nothing.
#include "iso/direct/block_list.glsl"
#include "iso/pmb/params.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer Nodes { vec2 minmax_nodes[]; };
layout(binding = 1) buffer Blocks { BlockListHeader block_header; uint occupied_blocks[]; };

void main() {
    // Workgroups spread over x and y (tessera_gpu::spread_groups).
    uint id = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    uvec3 d = params.block_dims;
    if (id >= d.x * d.y * d.z) {
        return;
    }
    uvec3 node_size = uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    uvec3 first_cell = pmb_block_of(id) * PMB_BLOCK;
    uvec3 first = first_cell / node_size;
    uvec3 last = min((first_cell + PMB_BLOCK - 1u) / node_size, params.node_dims - 1u);
    float iso = params.isovalue;
    bool occupied = false;
    for (uint z = first.z; z <= last.z; ++z) {
        for (uint y = first.y; y <= last.y; ++y) {
            for (uint x = first.x; x <= last.x; ++x) {
                vec2 range = minmax_nodes[(z * params.node_dims.y + y) * params.node_dims.x + x];
                occupied = occupied || (range.x <= iso && iso <= range.y);
            }
        }
    }
    if (occupied) {
        occupied_blocks[atomicAdd(block_header.count, 1u)] = id;
    }
}
