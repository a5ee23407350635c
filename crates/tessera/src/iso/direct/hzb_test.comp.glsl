#version 460
// The occlusion test of the compute path's culling, one invocation per block: counts the
// blocks whose (min, max) holds the isovalue and, of those not drawn in the first pass, lists
// the ones that may be visible for the second pass. A block may be visible when its cell box
// reaches the near plane, or when over the pixels its box could cover (a pixel's margin) the
// max-depth pyramid of the first pass holds a depth at or behind the box's nearest point.
#include "raster/hzb.glsl"
#include "iso/direct/block_list.glsl"
#include "iso/direct/cell_box.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 256) in;
layout(binding = 0) readonly buffer Nodes { vec2 minmax_nodes[]; };
// The number of the last frame each block owned a pixel in (resolve.comp.glsl): the blocks
// of the last frame's number were drawn in the first pass.
layout(binding = 1) readonly buffer BlockFlags { uint block_flags[]; };
layout(binding = 2) readonly buffer Hzb { float hzb[]; };
// Pass B's list; its dispatch arguments (one workgroup per block) grow as blocks are listed.
layout(binding = 3) buffer NewBlocks { BlockListHeader new_list; uint new_blocks[]; };
// [0] occupied blocks, [1] blocks listed for pass B
layout(binding = 4) buffer Stats { uint stats[]; };
// Per block, the box of the cells that made triangles and the isovalue's bits when it was last
// extracted (iso/direct/cell_box.glsl).
layout(binding = 5) readonly buffer CellBoxes { uvec2 cell_boxes[]; };

layout(push_constant) uniform HzbTestParams {
    mat4 grid_to_clip;
    uvec4 dims;   // xyz samples per axis, w pyramid levels
    uvec4 size;   // xy frame width and height
    vec4 iso;     // x the isovalue
    uint first_pass_number;  // the flag of the blocks drawn in the first pass
} params;

#include "raster/hzb_test.glsl"

bool may_be_visible(uvec3 block, uint block_id) {
    uvec3 lo = block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    uvec3 hi = min(lo + uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z), params.dims.xyz - 1u);
    // Where the block was extracted at this isovalue, its triangles lie in the cells that
    // made them: test their box.
    cell_box_narrow(cell_boxes[block_id], params.iso.x, lo, hi);
    return hzb_box_may_be_visible(params.grid_to_clip, vec3(lo), vec3(hi), params.size.xy,
                                  params.dims.w);
}

shared uint group_occupied;
shared uint group_new;
shared uint group_base;

void main() {
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        group_occupied = 0u;
        group_new = 0u;
    }
    barrier();
    uvec3 dims = params.dims.xyz;
    uvec3 block_dims = (dims - 2u) / uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + 1u;
    uint b = FLAT_INVOCATION;
    bool listed = false;
    uint slot = 0u;
    if (b < block_dims.x * block_dims.y * block_dims.z) {
        vec2 range = minmax_nodes[b];
        float iso = params.iso.x;
        if (iso >= range.x && iso <= range.y) {
            atomicAdd(group_occupied, 1u);
            uvec3 block = uvec3(b % block_dims.x, (b / block_dims.x) % block_dims.y,
                                b / (block_dims.x * block_dims.y));
            if (block_flags[b] != params.first_pass_number && may_be_visible(block, b)) {
                listed = true;
                slot = atomicAdd(group_new, 1u);
            }
        }
    }
    barrier();
    if (me == 0u) {
        if (group_occupied > 0u) {
            atomicAdd(stats[0], group_occupied);
        }
        if (group_new > 0u) {
            group_base = atomicAdd(new_list.count, group_new);
            GROW_INDIRECT_ARGS3(new_list.args, group_base + group_new, 1u);
            atomicAdd(stats[1], group_new);
        }
    }
    barrier();
    if (listed) {
        new_blocks[group_base + slot] = b;
    }
}
