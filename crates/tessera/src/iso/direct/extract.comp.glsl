#version 460
// Compute path of direct isosurface extraction: the task and mesh stages' work in one compute
// workgroup per 8×8×4 block, for GPUs whose graphics stages run on few units, reading the
// block's samples from shared memory (common/held_samples.glsl). Triangles go to
// the shared compute rasterizer's list (clip-space corners) with their shading attributes
// beside them; the workgroup reserves its slots with one atomic. Each corner's attributes carry
// its block's linear id (`maker`), so a resolve knows which blocks own pixels. With BLOCK_LIST
// defined (occlusion culling), workgroups take their blocks from a list (linear ids) instead
// of the block grid. With RASTER_IN_EXTRACTION defined, the workgroup then draws its triangles
// into the frame itself (raster/raster_draw.glsl), with no raster pass after it. With
// HIDDEN_CELLS_LEFT_OUT defined (culling's second pass, with a block list), a cell makes no
// triangles where its box fails the occlusion test against the first pass's max-depth pyramid
// (raster/hzb_test.glsl): most blocks that pass their own test own no pixel, and most of their
// cells lie behind what the first pass drew.
#if defined(DIRECT_SUBGROUP_SCAN) && DIRECT_SUBGROUP_SCAN
#extension GL_KHR_shader_subgroup_arithmetic : require
// Subgroup arithmetic where the device has it for compute shaders (compute::extract_defines):
// the prefix sums and the cell box's minima and maxima.
#define DIRECT_SUBGROUPS 1
#else
#define DIRECT_SUBGROUPS 0
#endif
#ifdef RASTER_IN_EXTRACTION
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_KHR_memory_scope_semantics : require
#if defined(RASTER_SUBGROUP_WALK) && RASTER_SUBGROUP_WALK
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#endif
#endif
#include "common/volume.glsl"
#include "common/mc_tables.glsl"
#include "common/mc_cell.glsl"
#include "common/grid_world.glsl"
#include "iso/direct/params.glsl"
#include "iso/direct/block_list.glsl"
#ifdef BLOCK_LIST
#define CELL_BOX_RECORD_SUBGROUPS DIRECT_SUBGROUPS
#include "iso/direct/cell_box_record.glsl"
#endif
#include "iso/direct/attributes.glsl"
#include "raster/raster.glsl"
#include "common/indirect_args.glsl"
#include "common/ablation.glsl"

// Invocations per block. With 32 (8 cells each), a block held too few invocations to hide the
// latency of its dependent steps, as the meshlet extraction found (docs/BENCHMARKS.md, run
// 43), and 32-invocation workgroups leave half an SM's warps unused where a GPU keeps at most
// 32 workgroups on one. A block list holds occupied blocks only, and one cell per invocation
// is fastest there; the whole grid's workgroups are mostly empty blocks that return at once,
// and 2 cells per invocation are fastest there (run 121).
#ifdef BLOCK_LIST
#define EXTRACT_INVOCATIONS 256
#else
#define EXTRACT_INVOCATIONS 128
#endif
layout(local_size_x = EXTRACT_INVOCATIONS) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) readonly buffer Nodes { vec2 minmax_nodes[]; };
// The block's samples with a one-sample apron, loaded once into shared memory.
#define HELD_SAMPLES_SIZE uvec3(BLOCK_X + 3u, BLOCK_Y + 3u, BLOCK_Z + 3u)
#define HELD_SAMPLES_MAX ((BLOCK_X + 3u) * (BLOCK_Y + 3u) * (BLOCK_Z + 3u))
#define HELD_SAMPLES_LOADERS uint(EXTRACT_INVOCATIONS)
#include "common/held_samples.glsl"
#define WORKGROUP_SCAN_SIZE EXTRACT_INVOCATIONS
#define WORKGROUP_SCAN_SUBGROUPS DIRECT_SUBGROUPS
#include "common/workgroup_scan.glsl"
#ifdef RASTER_IN_EXTRACTION
// Read back by the workgroup's other invocations, which draw them.
layout(binding = 2) coherent buffer Triangles { RasterTriangle triangles[]; };
#else
layout(binding = 2) writeonly buffer Triangles { RasterTriangle triangles[]; };
#endif
layout(binding = 3) writeonly buffer Attributes { TriangleAttributes attributes[]; };
// The rasterizer's counts: triangle_count, then its dispatch arguments, grown here as slots
// are reserved (zero before the pass), so the raster pass may follow without a pass between.
layout(binding = 4) buffer Counts {
    uint triangle_count;
    uint raster_dispatch[3];
};
// [0] triangles emitted (may exceed the capacity: then the frame is incomplete), [1] blocks
// that reached classification, [2] (HIDDEN_CELLS_LEFT_OUT) triangles of cells left out as
// hidden.
layout(binding = 5) buffer Stats { uint stats[]; };
#ifdef BLOCK_LIST
// A block list: its length, the indirect dispatch arguments (a 2-D grid of workgroups when
// one row would exceed the device's limit), then linear block ids.
layout(binding = 6) readonly buffer Blocks { BlockListHeader block_header; uint block_list[]; };
// Per block, the box of its cells that made triangles (iso/direct/cell_box.glsl) and the bits
// of the isovalue it was made at: what the occlusion test of later frames tests instead of
// the block's whole box.
layout(binding = 7) writeonly buffer CellBoxes { uvec2 cell_boxes[]; };
#define RASTER_BINDING 8
#else
#define RASTER_BINDING 6
#endif
#if defined(RASTER_IN_EXTRACTION) || defined(HIDDEN_CELLS_LEFT_OUT)
// How the triangles are drawn into the frame: the raster pass's push constants (RasterParams),
// written into a buffer since this pass's are full. The cells' occlusion test reads its size.
layout(binding = RASTER_BINDING + 2) readonly buffer RasterPassParams {
    uvec2 size;
    uint capacity;
    uint index_base;
    uint frame_number;
    int hidden_winding;
} raster_pass;
#endif
#ifdef RASTER_IN_EXTRACTION
// The frame the triangles are drawn into (raster/mod.rs).
layout(binding = RASTER_BINDING) buffer Frame { uint64_t depth_payload[]; };
layout(binding = RASTER_BINDING + 1) writeonly buffer TileFrames { uint tile_frames[]; };
#include "raster/raster_draw.glsl"
#endif
#ifdef HIDDEN_CELLS_LEFT_OUT
// The first pass's max-depth pyramid (raster/hzb.glsl).
layout(binding = RASTER_BINDING + 3) readonly buffer Hzb { float hzb[]; };
#include "raster/hzb.glsl"
#include "raster/hzb_test.glsl"

// Whether every triangle of `cell` lies behind what the first pass drew.
bool cell_hidden(uvec3 cell) {
    uvec2 size = raster_pass.size;
    return !hzb_box_may_be_visible(params.grid_to_clip, vec3(cell), vec3(cell + 1u), size,
                                   hzb_level_count(size));
}
#endif

const uint CELLS = BLOCK_X * BLOCK_Y * BLOCK_Z;
const uint PER_THREAD = CELLS / uint(EXTRACT_INVOCATIONS);
shared uint base;
#ifdef SPREAD_CORNERS
#ifndef BLOCK_LIST
#error "SPREAD_CORNERS needs one cell per invocation (BLOCK_LIST)"
#endif
// For each of the block's triangles in slot order, the invocation whose cell made it; for
// each invocation, its cell's table row and its first triangle among the block's.
shared uint triangle_maker[CELLS * MC_MAX_TRIANGLES];
shared uint corner_maker_row[EXTRACT_INVOCATIONS];
shared uint corner_maker_first[EXTRACT_INVOCATIONS];
#endif

// The block-local cell `id` (x fastest).
uvec3 cell_of_invocation(uint id) {
    return uvec3(id % BLOCK_X, (id / BLOCK_X) % BLOCK_Y, id / (BLOCK_X * BLOCK_Y));
}

// Corner `j` of the triangle in `slot`: the vertex on edge `corner` of `cell`'s table row
// `row` (its 3 t + j-th), with its normal and the block that made it, `block_id`.
void write_corner(uvec3 cell, uint row, uint corner, uint slot, uint j, uint block_id) {
    uvec3 dims = params.dims.xyz;
    vec3 p;
    vec3 normal;
    uint edge = mc_tri_edge(row, corner);
    uvec3 start = cell + mc_corner_offset(MC_EDGE_CORNERS[edge] & 15u);
    if (!ablation_stands_in_for_vertex(start, p, normal)) {
        held_edge_vertex(cell, edge, params.isovalue, dims, p, normal);
    }
    triangles[slot].clip[j] = params.grid_to_clip * vec4(p, 1.0);
    attributes[slot].corners[j] = CornerAttributes(grid_normal_to_world(normal, params.grid_to_world.xyz), block_id);
}

void main() {
    uint me = gl_LocalInvocationIndex;
    uvec3 dims = params.dims.xyz;
    float iso = params.isovalue;
    uint capacity = params.triangle_capacity;
    uvec3 block_dims = (dims - 2u) / uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + 1u;
#ifdef BLOCK_LIST
    uint listed = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (listed >= block_header.count) {
        return;  // the last row of a 2-D grid; uniform across the workgroup
    }
    uint block_id = block_list[listed];
    uvec3 block = uvec3(block_id % block_dims.x, (block_id / block_dims.x) % block_dims.y,
                        block_id / (block_dims.x * block_dims.y));
#else
    uvec3 block = gl_WorkGroupID;
    uint block_id = block.x + block_dims.x * (block.y + block_dims.y * block.z);
#endif
    vec2 range = minmax_nodes[block_id];
    if (iso < range.x || iso > range.y) {
        return;  // uniform across the workgroup
    }
    uvec3 block_first = block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    held_samples_load(block_first, block_first + uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z), dims);
#if EXTRACTION_ABLATION == ABLATION_SAMPLES_ONLY
    return;  // the samples are in shared memory, which other invocations could read
#endif

#ifdef BLOCK_LIST
    cell_box_record_begin();
    barrier();
#endif
    uint rows[PER_THREAD];  // table rows (case and ambiguous-face choices)
    uint total = 0u;
    uint hidden = 0u;  // triangles of this invocation's cells left out as hidden
    uvec3 made_lo = uvec3(0xffffffffu);  // the box of this invocation's cells with triangles
    uvec3 made_hi = uvec3(0u);
    for (uint k = 0u; k < PER_THREAD; ++k) {
        uvec3 local = cell_of_invocation(me * PER_THREAD + k);
        uvec3 cell = block_first + local;
        rows[k] = 0u;  // case 0's row: no triangles
        if (all(lessThan(cell, dims - 1u))) {
            float corners[8];
            held_cell_corners(cell, corners);
            rows[k] = mc_row_of_corners(corners, mc_case_of_corners(corners, iso), iso);
        }
        uint n = mc_tri_count(rows[k]);
        if (n > 0u) {
            // The cell box records where the surface lies, hidden or not.
            made_lo = min(made_lo, local);
            made_hi = max(made_hi, local);
#ifdef HIDDEN_CELLS_LEFT_OUT
            if (cell_hidden(cell)) {
                hidden += n;
                rows[k] = 0u;
                n = 0u;
            }
#endif
        }
        total += n;
    }
#ifdef BLOCK_LIST
#if DIRECT_SUBGROUPS
    cell_box_record_add_in_subgroup(made_lo, made_hi);
#else
    if (total + hidden > 0u) {
        cell_box_record_add(made_lo, made_hi);
    }
#endif
#endif
    uvec3 totals;
    uint below = workgroup_exclusive_scan(uvec3(total, hidden, 0u), totals).x;
    uint wg_total = totals.x;
    if (me == 0u) {
        uint first = atomicAdd(stats[0], wg_total);
        atomicAdd(stats[1], 1u);
#ifdef HIDDEN_CELLS_LEFT_OUT
        if (totals.y > 0u) {
            atomicAdd(stats[2], totals.y);
        }
#endif
        // Slots past the capacity are dropped; the count stays exact (see Stats).
        uint kept = first >= capacity ? 0u : min(wg_total, capacity - first);
#if EXTRACTION_ABLATION == ABLATION_ANALYSIS_ONLY
        kept = 0u;  // no triangle is written, so none is counted for the raster pass
#endif
        if (kept > 0u) {
            atomicAdd(triangle_count, kept);
            GROW_INDIRECT_ARGS3(raster_dispatch, first + kept, RASTER_GROUP_SIZE);
        }
        base = first;
#ifdef BLOCK_LIST
        cell_boxes[block_id] = uvec2(cell_box_recorded(wg_total + totals.y > 0u), floatBitsToUint(iso));
#endif
    }
    barrier();
#if EXTRACTION_ABLATION == ABLATION_ANALYSIS_ONLY
    return;
#endif

#ifdef SPREAD_CORNERS
    // Every corner of the block's triangles to its own invocation, in slot order: the cell that
    // made a triangle is found from the shared list of makers.
    uint row = rows[0];
    corner_maker_row[me] = row;
    corner_maker_first[me] = below;
    for (uint t = 0u; t < mc_tri_count(row); ++t) {
        triangle_maker[below + t] = me;
    }
    barrier();
    for (uint c = me; c < 3u * wg_total; c += uint(EXTRACT_INVOCATIONS)) {
        uint t = c / 3u;
        uint slot = base + t;
        if (slot < capacity) {
            uint maker = triangle_maker[t];
            write_corner(block_first + cell_of_invocation(maker), corner_maker_row[maker],
                         3u * (t - corner_maker_first[maker]) + (c - 3u * t), slot, c - 3u * t,
                         block_id);
        }
    }
#else
    uint slot = base + below;
    for (uint k = 0u; k < PER_THREAD; ++k) {
        uint row = rows[k];
        uint n = mc_tri_count(row);
        if (n == 0u) {
            continue;
        }
        uvec3 cell = block_first + cell_of_invocation(me * PER_THREAD + k);
        for (uint t = 0u; t < n; ++t, ++slot) {
            if (slot >= capacity) {
                continue;
            }
            for (uint j = 0u; j < 3u; ++j) {
                write_corner(cell, row, 3u * t + j, slot, j, block_id);
            }
        }
    }
#endif
#ifdef RASTER_IN_EXTRACTION
    // The workgroup's triangles, drawn as the raster pass draws them. Each invocation takes
    // every EXTRACT_INVOCATIONS-th from its own, so that cells with many triangles keep no
    // invocation waiting.
    memoryBarrierBuffer();
    barrier();
    RasterPass pass = RasterPass(raster_pass.size, raster_pass.frame_number, raster_pass.hidden_winding);
    uint end = RASTER_VARIANT == 4 ? base : min(base + wg_total, capacity);
#if RASTER_SUBGROUP_WALK
    // As many steps for every invocation (base and end are the workgroup's), so that each
    // subgroup walks its large triangles together.
    for (uint first = base; first < end; first += uint(EXTRACT_INVOCATIONS)) {
        uint s = first + me;
        bool valid = s < end;
        vec4 clip[3] = valid ? triangles[s].clip : vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
        raster_draw_triangle_in_subgroup(pass, valid, clip[0], clip[1], clip[2], raster_pass.index_base + s);
    }
#else
    for (uint s = base + me; s < end; s += uint(EXTRACT_INVOCATIONS)) {
        raster_draw_triangle(pass, triangles[s].clip[0], triangles[s].clip[1], triangles[s].clip[2],
                             raster_pass.index_base + s);
    }
#endif
#endif
}
