// Recording a block's cell box (iso/direct/cell_box.glsl) in the workgroup that extracts the
// block: each invocation adds the box of its cells that made triangles, then one packs it.
#ifndef ISO_DIRECT_CELL_BOX_RECORD_GLSL
#define ISO_DIRECT_CELL_BOX_RECORD_GLSL
#include "iso/direct/cell_box.glsl"

shared uint cell_box_lo[3];
shared uint cell_box_hi[3];

// Empties the box; a barrier must follow before any cell_box_record_add.
void cell_box_record_begin() {
    if (gl_LocalInvocationIndex < 3u) {
        cell_box_lo[gl_LocalInvocationIndex] = 0xffffffffu;
        cell_box_hi[gl_LocalInvocationIndex] = 0u;
    }
}

// Grows the box by cells `lo` to `hi` (local to the block).
void cell_box_record_add(uvec3 lo, uvec3 hi) {
    for (uint a = 0u; a < 3u; ++a) {
        atomicMin(cell_box_lo[a], lo[a]);
        atomicMax(cell_box_hi[a], hi[a]);
    }
}

#if defined(CELL_BOX_RECORD_SUBGROUPS) && CELL_BOX_RECORD_SUBGROUPS
// cell_box_record_add for a whole subgroup at once, from uniform control flow (the includer
// enables subgroup arithmetic): an invocation with no cells to add passes the empty box (`lo`
// all ones, `hi` zero), and one invocation adds the subgroup's box, so that the shared atomics
// meet each address once a subgroup rather than once an invocation with triangles.
void cell_box_record_add_in_subgroup(uvec3 lo, uvec3 hi) {
    uvec3 group_lo = subgroupMin(lo);
    uvec3 group_hi = subgroupMax(hi);
    if (subgroupElect() && group_lo.x <= group_hi.x) {
        cell_box_record_add(group_lo, group_hi);
    }
}
#endif

// The packed box after every addition (and a barrier); with `made_triangles` false, a block
// without triangles, no box (its whole box stands).
uint cell_box_recorded(bool made_triangles) {
    return made_triangles
        ? cell_box_pack(uvec3(cell_box_lo[0], cell_box_lo[1], cell_box_lo[2]),
                        uvec3(cell_box_hi[0], cell_box_hi[1], cell_box_hi[2]))
        : 0u;
}

#endif
