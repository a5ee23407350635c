// Region analysis (paper C §3.2.1) of one occupied block by one workgroup of
// MESHLET_WORKGROUP invocations (a multiple of the block's eighths, each eighth's cells split
// evenly among its invocations): the partition into subblocks that each fit a meshlet, exactly
// as tessera_data::meshlets::partition makes it, and the block's reservation in the output
// buffers. Writes `payload` (declared by the includer: task payload or shared memory).
// The block's totals and where each invocation's occupied cells go come from one prefix sum
// over the invocations (iso/meshlets/scan.glsl); per-eighth sums are shared-memory atomics.
// Needs iso/meshlets/{params,buffers,payload,samples,subblock,scan}.glsl and the
// marching-cubes headers (common/mc_edges.glsl among them).

// Per eighth: occupied cells, their triangles and the crossed edges they own; summed over the
// eighth's invocations with atomics, only for a block that does not fit whole (its partition).
shared uint s_eighth_cells[MESHLET_EIGHTHS];
shared uint s_eighth_triangles[MESHLET_EIGHTHS];
shared uint s_eighth_core[MESHLET_EIGHTHS];
// Crossed padding edges of the eighth's own box, and its invocations' shares of those of its
// quarter's box (the sum over a quarter's eighths is that box's count).
shared uint s_eighth_padding[MESHLET_EIGHTHS];
shared uint s_quarter_padding[MESHLET_EIGHTHS];
// Where each eighth's occupied cells start in the block's list of them.
shared uint s_first_cell[MESHLET_EIGHTHS];
// The Morton codes of the block's occupied cells in order.
shared uint s_codes[BLOCK_X * BLOCK_Y * BLOCK_Z];
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
// Per Morton code of an occupied cell: its table row (bits 0-15) and case (bits 16-23), for
// an extraction in the same workgroup, which then need not classify the cell again.
shared uint s_code_rows[BLOCK_X * BLOCK_Y * BLOCK_Z];
#endif
#ifdef MESHLET_FITTING_BLOCKS_ONLY
// This invocation's part of the analysis, for an extraction in the same workgroup of a block
// that fits one meshlet whole: the invocation's occupied cells are entries analysed_first_cell
// .. + analysed_cells of the block's list, and the analysis's prefix sums and totals of core
// vertices, padding vertices and triangles number the meshlet as its own counting would.
uint analysed_first_cell;
uint analysed_cells;
uvec3 analysed_prefix;
uvec3 analysed_totals;
#endif

const uint EIGHTHS_PER_QUARTER = MESHLET_EIGHTHS / 4u;
const uint INVOCATIONS_PER_EIGHTH = MESHLET_WORKGROUP / MESHLET_EIGHTHS;
const uint CELLS_PER_INVOCATION = MESHLET_EIGHTH_CELLS / INVOCATIONS_PER_EIGHTH;

bool meshlet_fits(uint vertices, uint triangles, uint cells) {
    return vertices <= MESHLET_MAX_VERTICES && triangles <= MESHLET_MAX_TRIANGLES
        && cells <= MESHLET_MAX_OCCUPIED_CELLS;
}

// Padding crossings of the box of `count` codes from `first_code`, the share of invocation
// `part` of `parts` (contiguous runs of the box's points).
uint meshlet_padding_share(uvec3 block_origin, uint first_code, uint count, uint part, uint parts,
                           float iso) {
    uvec3 lo = block_origin + meshlet_cell_of_code(first_code);
    uvec3 size = meshlet_cell_of_code(first_code + count - 1u) - meshlet_cell_of_code(first_code) + 1u;
    uvec3 hi = mc_box_end(lo, size, params.volume_dims);
    uint points = meshlet_box_points(lo, hi);
    uint share = (points + parts - 1u) / parts;
    uint first = min(part * share, points);
    return meshlet_padding_crossings(lo, hi, first, min(first + share, points), iso);
}

void meshlet_add_subblock(inout uint n, inout uint vertex_cursor, inout uint triangle_cursor,
                          uint first_code, uint code_count, uint vertices, uint triangles,
                          uint first_cell, uint cells) {
    payload.subblocks[n] = MeshletSubblock(first_code | code_count << 16,
                                           vertex_cursor | triangle_cursor << 16,
                                           vertices | triangles << 16, first_cell | cells << 16);
    n += 1u;
    vertex_cursor += vertices;
    triangle_cursor += (triangles + 3u) & ~3u;
}

// Partitions block `occupied_blocks[listed]` into `payload` and reserves its output; ends
// with a barrier, so every invocation may read the payload after it.
void meshlet_analyse(uint listed) {
    uint me = gl_LocalInvocationIndex;
    float iso = params.isovalue;
    uvec3 block_origin = meshlet_block_origin(occupied_blocks[listed]);
    uvec3 last_cell = params.volume_dims - 1u;
    if (me < MESHLET_EIGHTHS) {
        s_eighth_cells[me] = 0u;
        s_eighth_triangles[me] = 0u;
        s_eighth_core[me] = 0u;
        s_eighth_padding[me] = 0u;
        s_quarter_padding[me] = 0u;
    }
    // Ends with a barrier: the sums above start at zero for everyone.
    held_samples_load(block_origin,
                      mc_box_end(block_origin, uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z), params.volume_dims),
                      params.volume_dims);

    uint cells = 0u;
    uint triangles = 0u;
    uint core = 0u;
    uint occupied_mask = 0u;
    // This invocation's cells: a run of its eighth's.
    uint e = me / INVOCATIONS_PER_EIGHTH;
    uint part = me % INVOCATIONS_PER_EIGHTH;
    uint eighth = e * MESHLET_EIGHTH_CELLS;
    uint first_k = part * CELLS_PER_INVOCATION;
    for (uint k = first_k; k < first_k + CELLS_PER_INVOCATION; ++k) {
        uvec3 cell = block_origin + meshlet_cell_of_code(eighth + k);
        if (any(greaterThanEqual(cell, last_cell))) {
            continue;
        }
        float corners[8];
        held_cell_corners(cell, corners);
        uint case_index = mc_case_of_corners(corners, iso);
        if (MC_EDGE_MASK[case_index] == 0u) {
            continue;
        }
        cells += 1u;
        occupied_mask |= 1u << k;
        uint row = mc_row_of_corners(corners, case_index, iso);
        triangles += mc_tri_count(row);
        core += mc_case_owned_crossings(case_index);
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
        s_code_rows[eighth + k] = row | case_index << 16;
#endif
    }
    // The block box's points split among the invocations as the extraction of a whole-block
    // subblock splits them, so that extraction may number its padding vertices from this.
    uint block_padding = meshlet_padding_share(block_origin, 0u, BLOCK_X * BLOCK_Y * BLOCK_Z,
                                               me, MESHLET_WORKGROUP, iso);
    // Invocations hold their eighth's cells in Morton order, so the prefix of the occupied
    // cells is where this invocation's go in the block's list; the totals are the whole
    // block's vertices (core and padding), triangles and occupied cells.
    // Cells and triangles share a word: a block has at most 256 cells and 1280 triangles.
    uvec3 block;
    uvec3 before = meshlet_scan_counts(uvec3(cells | triangles << 16, core, block_padding),
                                       block);
    uint block_triangles = block.x >> 16;
    // Vertices (core and padding), triangles, occupied cells.
    uvec3 block_counts = uvec3(block.y + block.z, block_triangles, block.x & 0xffffu);
    uint cells_before = before.x & 0xffffu;
#ifdef MESHLET_FITTING_BLOCKS_ONLY
    analysed_first_cell = cells_before;
    analysed_cells = cells;
    analysed_prefix = uvec3(before.y, before.z, before.x >> 16);
    analysed_totals = uvec3(block.y, block.z, block_triangles);
#endif
    if (part == 0u) {
        s_first_cell[e] = cells_before;
    }
    uint at = cells_before;
    for (uint k = first_k; k < first_k + CELLS_PER_INVOCATION; ++k) {
        if ((occupied_mask & (1u << k)) != 0u) {
            s_codes[at] = eighth + k;
            at += 1u;
        }
    }
    // Most blocks fit one meshlet whole; only the others need their quarters' and eighths'
    // padding (counted for eighths with occupied cells only, the partition's rule), and a
    // barrier before one invocation partitions from those sums. The totals are the same in
    // every invocation, so the branch is uniform.
    bool block_fits = meshlet_fits(block_counts.x, block_counts.y, block_counts.z);
#ifdef MESHLET_FITTING_BLOCKS_ONLY
    if (!block_fits) {
        // Left to the split pass, which analyses the block again.
        if (me == 0u) {
            split_blocks[atomicAdd(split_header.count, 1u)] = listed;
            payload.subblock_count = 0u;
        }
        barrier();
        return;
    }
#else
    if (!block_fits) {
        atomicAdd(s_eighth_cells[e], cells);
        atomicAdd(s_eighth_triangles[e], triangles);
        atomicAdd(s_eighth_core[e], core);
        const uint QUARTER_CELLS = EIGHTHS_PER_QUARTER * MESHLET_EIGHTH_CELLS;
        const uint QUARTER_INVOCATIONS = MESHLET_WORKGROUP / 4u;
        atomicAdd(s_eighth_padding[e], meshlet_padding_share(block_origin, eighth,
            MESHLET_EIGHTH_CELLS, part, INVOCATIONS_PER_EIGHTH, iso));
        atomicAdd(s_quarter_padding[e], meshlet_padding_share(block_origin,
            (me / QUARTER_INVOCATIONS) * QUARTER_CELLS, QUARTER_CELLS, me % QUARTER_INVOCATIONS,
            QUARTER_INVOCATIONS, iso));
        barrier();
    }
#endif

    if (me == 0u) {
        uint total = block_counts.z;
        uint n = 0u;
        uint vertex_cursor = 0u;
        uint triangle_cursor = 0u;
        if (total == 0u) {
            // The block's range holds iso, yet no cell has a corner below and one above.
        } else if (block_fits) {
            meshlet_add_subblock(n, vertex_cursor, triangle_cursor, 0u, BLOCK_X * BLOCK_Y * BLOCK_Z,
                                 block_counts.x, block_counts.y, 0u, total);
        } else {
#ifndef MESHLET_FITTING_BLOCKS_ONLY
            for (uint q = 0u; q < MESHLET_EIGHTHS; q += EIGHTHS_PER_QUARTER) {
                uint quarter_v = 0u;
                uint quarter_t = 0u;
                uint quarter_c = 0u;
                for (uint i = q; i < q + EIGHTHS_PER_QUARTER; ++i) {
                    quarter_v += s_eighth_core[i] + s_quarter_padding[i];
                    quarter_t += s_eighth_triangles[i];
                    quarter_c += s_eighth_cells[i];
                }
                if (quarter_c == 0u) {
                    continue;
                }
                if (meshlet_fits(quarter_v, quarter_t, quarter_c)) {
                    meshlet_add_subblock(n, vertex_cursor, triangle_cursor,
                                         q * MESHLET_EIGHTH_CELLS,
                                         EIGHTHS_PER_QUARTER * MESHLET_EIGHTH_CELLS,
                                         quarter_v, quarter_t, s_first_cell[q], quarter_c);
                    continue;
                }
                // An eighth always fits (tessera_data::meshlets::partition).
                for (uint i = q; i < q + EIGHTHS_PER_QUARTER; ++i) {
                    if (s_eighth_cells[i] != 0u) {
                        meshlet_add_subblock(n, vertex_cursor, triangle_cursor,
                                             i * MESHLET_EIGHTH_CELLS,
                                             MESHLET_EIGHTH_CELLS,
                                             s_eighth_core[i] + s_eighth_padding[i],
                                             s_eighth_triangles[i], s_first_cell[i],
                                             s_eighth_cells[i]);
                    }
                }
            }
#endif
        }
        payload.block = listed;
        payload.subblock_count = n;
        payload.base_meshlet = 0u;
        payload.base_vertex = 0u;
        payload.base_triangle = 0u;
        if (n > 0u) {
            // Totals keep counting past the capacities, so the host learns what to grow to.
            payload.base_meshlet = atomicAdd(counters.meshlets, n);
            payload.base_vertex = atomicAdd(counters.vertices, vertex_cursor);
            payload.base_triangle = atomicAdd(counters.triangles, triangle_cursor);
            bool fits = payload.base_meshlet + n <= params.meshlet_capacity
                && payload.base_vertex + vertex_cursor <= params.vertex_capacity
                && payload.base_triangle + triangle_cursor <= params.triangle_capacity;
            if (!fits) {
                atomicOr(counters.overflow, MESHLET_OVERFLOW_CAPACITY);
                payload.subblock_count = 0u;
            }
        }
        block_meshlets[listed] = uvec2(payload.base_meshlet, n);
    }
#ifndef MESHLET_ANALYSIS_IN_WORKGROUP
    // The mesh workgroups read the occupied cells' codes from the payload, four to a word;
    // an extraction in this workgroup reads s_codes itself. The codes need a barrier first,
    // which a block that does not fit had before its partition.
    if (block_fits) {
        barrier();
    }
    for (uint w = me; w < BLOCK_X * BLOCK_Y * BLOCK_Z / 4u; w += MESHLET_WORKGROUP) {
        payload.cells[w] = (s_codes[4u * w] & 255u) | (s_codes[4u * w + 1u] & 255u) << 8
            | (s_codes[4u * w + 2u] & 255u) << 16 | (s_codes[4u * w + 3u] & 255u) << 24;
    }
#endif
    barrier();
}
