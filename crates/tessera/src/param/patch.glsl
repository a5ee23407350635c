// Patches and the LOD stage's counters (param/lod.rs documents both).
//
// A shader defines PARAM_STATE_BINDING before including this to get the state buffer: a header
// of statistics, then one LodEntry per list: entries[0] = patches to render, entries[1 + s] =
// patches LOD step s evaluates. `count` is the number of patches appended (it may exceed the
// list's capacity; the excess was dropped and counted in `dropped`), x, y, z the indirect
// dispatch arguments lod_prepare writes from it.

#ifndef PARAM_PATCH_GLSL
#define PARAM_PATCH_GLSL

struct Patch {
    vec2 u;       // u0, u1
    vec2 v;       // v0, v1
    vec2 extent;  // screen extents (e_u, e_v) in raster pixels (patches to render)
    uint object;
    uint info;    // LOD step that emitted it | PATCH_OVER_THRESHOLD
};

const uint PATCH_OVER_THRESHOLD = 1u << 16;

struct LodEntry {
    uint count;
    uint x;
    uint y;
    uint z;
};

#ifdef PARAM_STATE_BINDING
layout(binding = PARAM_STATE_BINDING, std430) buffer LodState {
    uint culled;           // patches dropped by frustum culling
    uint limit_hits;       // patches rendered because the last step was reached
    uint resolution_hits;  // patches kept although f32 could not halve them further
    uint dropped;          // patches lost to full lists
    uint capture_count;    // LOD samples offered to the debug capture
    uint skipped_cells;    // point pass: triangles too large to rasterize
    uint pad0;
    uint pad1;
    LodEntry entries[];
};
#endif

// Workgroup index on a 2-D grid spread by lod_prepare.
uint param_group_index() {
    return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
}

#endif
