#version 460
// The graphics path of the PMB draw: per block of the extraction, a frustum test of its box
// and, when it passes, one indexed draw of its triangles. The indices are local to the block,
// so the draw's vertex offset is the block's first vertex; the survivors are packed and
// counted, and the count is what the indirect draw reads.
#include "iso/meshlet_draw/params.glsl"
#include "iso/pmb/format.glsl"
#include "iso/pmb_draw/blocks.glsl"

layout(local_size_x = PMB_DRAW_GROUP) in;

// VkDrawIndexedIndirectCommand.
struct DrawIndexedIndirectCommand {
    uint index_count;
    uint instance_count;
    uint first_index;
    int vertex_offset;
    uint first_instance;
};

layout(binding = 3) writeonly buffer Commands { DrawIndexedIndirectCommand commands[]; };

void main() {
    uint id = pmb_draw_group() * PMB_DRAW_GROUP + gl_LocalInvocationIndex;
    if (id >= block_count) {
        return;
    }
    PmbBlock b = descriptors[id];
    if (!pmb_block_in_frustum(b)) {
        return;
    }
    atomicAdd(triangles_drawn, b.triangle_count);
    commands[atomicAdd(blocks_drawn, 1u)] = DrawIndexedIndirectCommand(
        3u * b.triangle_count, 1u, b.first_index, int(b.first_vertex), 0u);
}
