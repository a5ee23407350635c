// What every PMB draw pass reads first: the number of blocks to draw with its indirect
// dispatch (raster::IndirectArgs's layout), the extraction's block descriptors, and the
// frame's draw counters. Needs iso/meshlet_draw/params.glsl (the draws share the meshlet
// draw's push constants) and iso/pmb/format.glsl.
#include "common/frustum.glsl"

layout(binding = 0) readonly buffer BlockCount { uint block_count; uint block_dispatch[3]; };
layout(binding = 1) readonly buffer Descriptors { PmbBlock descriptors[]; };
// Blocks that passed culling (on the graphics path also the number of indexed draws) and the
// triangles they hold, all of them, also those a full compute list could not take.
layout(binding = 2) buffer PmbDrawCounters { uint blocks_drawn; uint triangles_drawn; };

// The workgroup's index over a grid of workgroups spread in x and y.
uint pmb_draw_group() {
    return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
}

// Whether block `b` may reach the view, tested by its cells' box (PMB blocks store no
// bounds: the block coordinate gives them); always with MESHLET_BOUNDS_NONE.
bool pmb_block_in_frustum(PmbBlock b) {
    if (params.bounds == MESHLET_BOUNDS_NONE) {
        return true;
    }
    uvec3 size = uvec3(PMB_BLOCK_X, PMB_BLOCK_Y, PMB_BLOCK_Z);
    vec3 lo = vec3(uvec3(b.block[0], b.block[1], b.block[2]) * size);
    return box_in_frustum(params.grid_to_clip, lo, lo + vec3(size));
}
