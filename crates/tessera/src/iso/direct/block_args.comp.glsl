#version 460
// Turns the occupied-block count into the indirect arguments of one workgroup per block, a
// compute dispatch or a mesh-task draw, spread over x and y so no axis passes the 65,535
// every device accepts.
#include "iso/direct/block_list.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 1) in;
layout(binding = 0) buffer Blocks { BlockListHeader block_header; uint occupied_blocks[]; };

void main() {
    uint count = block_header.count;
    uint x = clamp(count, 1u, INDIRECT_MAX_GROUPS_X);
    block_header.args = uint[3](count == 0u ? 0u : x, (count + x - 1u) / x, 1u);
}
