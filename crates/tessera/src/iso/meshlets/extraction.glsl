// Extraction (paper C §3.2.2) of the meshlet of one subblock of `payload` by one workgroup of
// MESHLET_WORKGROUP invocations, PMB-style, in the CPU reference's order
// (tessera_data::meshlets::subblock): vertices of the crossed edges owned by the occupied
// cells, then of those owned by padding points; triangles by cell, each cell's in table order.
// Each sample of the subblock's closed box keeps, in shared memory, the crossed edges it owns
// and the local number of the first one's vertex, so triangles find theirs without search.
// Needs the marching-cubes headers, common/mc_vertex.glsl, common/mc_edges.glsl and
// iso/meshlets/{params,buffers,payload,samples,subblock}.glsl.

const uint MESHLET_CELLS_PER_EXTRACTOR = MESHLET_MAX_OCCUPIED_CELLS / MESHLET_WORKGROUP;
// Samples of the largest box: a block's cells plus one on each axis.
const uint MESHLET_BOX_POINTS = (BLOCK_X + 1u) * (BLOCK_Y + 1u) * (BLOCK_Z + 1u);
const uint MESHLET_INDEX_WORDS = (MESHLET_MAX_TRIANGLES + 3u) / 4u * 3u;

// Per sample of the box (x fastest) that owns a crossed edge: the local vertex of its first
// one (bits 0-15) and its owned crossings (bits 16-18: x, y, z edge).
shared uint s_point_vertices[MESHLET_BOX_POINTS];
shared uint s_index_words[MESHLET_INDEX_WORDS];
// Per vertex of the meshlet, its edge: the start sample relative to the box's minimum (4 bits
// per axis) and the axis (bits 12-13).
shared uint s_vertex_edges[MESHLET_MAX_VERTICES];
#ifndef MESHLET_ANALYSIS_IN_WORKGROUP
// Per occupied cell of the subblock: its table row (bits 0-15) and owned crossed edges
// (bits 16-18: x, y, z).
shared uint s_cell_rows[MESHLET_MAX_OCCUPIED_CELLS];
#endif
// The meshlet's AABB as float bits: positions are grid coordinates, never negative, so their
// bits order as their values and integer atomics find the extremes.
shared uint s_aabb_min[3];
shared uint s_aabb_max[3];

// The Morton code of the block's `i`-th occupied cell: from the analysis's list where it ran
// in this workgroup, else from the payload, four to a word.
uint meshlet_cell_code(uint i) {
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
    return s_codes[i];
#else
    return (payload.cells[i >> 2] >> ((i & 3u) * 8u)) & 255u;
#endif
}

// Entry `c` of the subblock's occupied cells (its list starts at `first_cell` of the block's):
// its table row (bits 0-15) and owned crossed edges (bits 16-18: x, y, z), from the analysis
// where it ran in this workgroup, else as the counting pass stored it.
uint meshlet_cell_entry(uint first_cell, uint c) {
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
    uint cached = s_code_rows[meshlet_cell_code(first_cell + c)];
    return (cached & 0xffffu) | mc_case_owned_mask(cached >> 16) << 16;
#else
    return s_cell_rows[c];
#endif
}

// Clears the subblock's packed indices and bounds; they are read after the next barrier.
void meshlet_clear_outputs() {
    for (uint w = gl_LocalInvocationIndex; w < MESHLET_INDEX_WORDS; w += MESHLET_WORKGROUP) {
        s_index_words[w] = 0u;
    }
    if (gl_LocalInvocationIndex < 3u) {
        s_aabb_min[gl_LocalInvocationIndex] = 0x7f800000u;  // +inf
        s_aabb_max[gl_LocalInvocationIndex] = 0u;
    }
}

uint meshlet_point_slot(uvec3 p, uvec3 lo, uvec3 points) {
    uvec3 d = p - lo;
    return (d.z * points.y + d.y) * points.x + d.x;
}

// `block_samples_held`: the workgroup already holds the samples of the block's box (the
// compute path, after the analysis); otherwise it loads its subblock's. Uniform across the
// workgroup.
void meshlet_extract(uint s, bool block_samples_held) {
    uint me = gl_LocalInvocationIndex;
    float iso = params.isovalue;
    uvec3 dims = params.volume_dims;
    MeshletSubblock sub = payload.subblocks[s];
    uint first_code = sub.codes & 0xffffu;
    uint code_count = sub.codes >> 16;
    uint first_cell = sub.cells & 0xffffu;
    uint cell_count = sub.cells >> 16;
    uvec3 block_origin = meshlet_block_origin(occupied_blocks[payload.block]);
    uvec3 lo = block_origin + meshlet_cell_of_code(first_code);
    uvec3 size = meshlet_cell_of_code(first_code + code_count - 1u) - meshlet_cell_of_code(first_code) + 1u;
    uvec3 hi = mc_box_end(lo, size, dims);
    if (!block_samples_held) {
        held_samples_load(lo, hi, params.volume_dims);
    }
    uvec3 points = hi - lo + 1u;
    uint box_points = meshlet_box_points(lo, hi);
    uint padding_share = (box_points + MESHLET_WORKGROUP - 1u) / MESHLET_WORKGROUP;
    uint padding_first = min(me * padding_share, box_points);
    uint padding_end = min(padding_first + padding_share, box_points);

#ifdef MESHLET_FITTING_BLOCKS_ONLY
    // The compute path's pass over blocks that fit one meshlet whole: the analysis in this
    // workgroup counted the block, its cells and box points split among the invocations as
    // this extraction splits them, and the includer cleared the outputs before the analysis,
    // whose barriers published that.
    uint cell_first = analysed_first_cell;
    uint cell_end = cell_first + analysed_cells;
    uvec3 first = analysed_prefix;
    uvec3 totals = analysed_totals;
#else
    // Counts: each invocation takes a run of cells and a run of box points.
    uint core_vertices = 0u;
    uint triangles = 0u;
    uint cell_first = me * MESHLET_CELLS_PER_EXTRACTOR;
    uint cell_end = clamp(cell_count, cell_first, cell_first + MESHLET_CELLS_PER_EXTRACTOR);
    for (uint c = cell_first; c < cell_end; ++c) {
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
        uint entry = meshlet_cell_entry(first_cell, c);
#else
        uvec3 cell = block_origin + meshlet_cell_of_code(meshlet_cell_code(first_cell + c));
        float corners[8];
        held_cell_corners(cell, corners);
        uint case_index = mc_case_of_corners(corners, iso);
        uint entry = mc_row_of_corners(corners, case_index, iso)
            | mc_case_owned_mask(case_index) << 16;
        s_cell_rows[c] = entry;
#endif
        triangles += mc_tri_count(entry & 0xffffu);
        core_vertices += bitCount(entry >> 16);
    }
    uint padding = meshlet_padding_crossings(lo, hi, padding_first, padding_end, iso);
    meshlet_clear_outputs();
    // Its barriers also publish the words and bounds just cleared.
    uvec3 totals;
    uvec3 first = meshlet_scan_counts(uvec3(core_vertices, padding, triangles), totals);
    uint expected = sub.counts;
    if (me == 0u && (totals.x + totals.y != (expected & 0xffffu) || totals.z != expected >> 16)) {
        atomicOr(counters.overflow, MESHLET_OVERFLOW_MISMATCH);
    }
#endif
    uint core_total = totals.x;
    uint vertices = core_total + totals.y;
    uint vertex_count = min(vertices, MESHLET_MAX_VERTICES);
    uint triangle_count = min(totals.z, MESHLET_MAX_TRIANGLES);
    uint first_vertex = payload.base_vertex + (sub.offsets & 0xffffu);
    uint first_triangle = payload.base_triangle + (sub.offsets >> 16);

    // Vertices, numbered in the reference's order: this invocation's cells, then its run of
    // box points. Numbering only records each vertex's edge; the vertex arithmetic then takes
    // one vertex per invocation, balanced whatever the cells' crossings, and with few values
    // live beside it.
    uint cell_items = cell_end - cell_first;
    uint items = cell_items + (padding_end - padding_first);
    uint local = first.x;
    for (uint i = 0u; i < items; ++i) {
        bool core = i < cell_items;
        uvec3 p;
        if (core) {
            p = block_origin + meshlet_cell_of_code(meshlet_cell_code(first_cell + cell_first + i));
        } else {
            uint j = padding_first + i - cell_items;
            p = mc_box_point(lo, points, j);
            if (i == cell_items) {
                local = core_total + first.y;
            }
            if (!any(equal(p, hi))) {
                continue;
            }
        }
        // A core cell lies inside the box: its case says which of its edges cross.
        uint owned = core ? meshlet_cell_entry(first_cell, cell_first + i) >> 16
                          : meshlet_owned_crossings(p, hi, iso);
        if (owned == 0u) {
            continue;
        }
        s_point_vertices[meshlet_point_slot(p, lo, points)] = local | owned << 16;
        uvec3 d = p - lo;
        for (; owned != 0u; owned &= owned - 1u, ++local) {
            if (local < vertex_count) {
                s_vertex_edges[local] = d.x | d.y << 4 | d.z << 8 | findLSB(owned) << 12;
            }
        }
    }
    barrier();

    vec3 lo_bound = vec3(uintBitsToFloat(0x7f800000u));
    vec3 hi_bound = vec3(0.0);
    for (uint v = me; v < vertex_count; v += MESHLET_WORKGROUP) {
        uint edge = s_vertex_edges[v];
        uvec3 p = lo + uvec3(edge & 15u, (edge >> 4) & 15u, (edge >> 8) & 15u);
        vec3 position;
        vec3 normal;
        if (!ablation_stands_in_for_vertex(p, position, normal)) {
            meshlet_edge_vertex(p, edge >> 12, iso, position, normal);
        }
        uint at = first_vertex + v;
        for (uint a = 0u; a < 3u; ++a) {
            positions[3u * at + a] = position[a];
            normals[3u * at + a] = normal[a];
        }
        lo_bound = min(lo_bound, position);
        hi_bound = max(hi_bound, position);
    }
    for (uint a = 0u; a < 3u; ++a) {
        atomicMin(s_aabb_min[a], floatBitsToUint(lo_bound[a]));
        atomicMax(s_aabb_max[a], floatBitsToUint(hi_bound[a]));
    }

    // Triangles: local indices packed into shared words, then copied out whole.
    uint t = 3u * first.z;  // the local index at hand
    for (uint c = cell_first; c < cell_end; ++c) {
        uvec3 cell = block_origin + meshlet_cell_of_code(meshlet_cell_code(first_cell + c));
        uint row = meshlet_cell_entry(first_cell, c) & 0xffffu;
        for (uint i = 0u; i < 3u * mc_tri_count(row); ++i, ++t) {
            uvec3 p;
            uint axis;
            mc_edge_owner(cell, mc_tri_edge(row, i), p, axis);
            uint vertices = s_point_vertices[meshlet_point_slot(p, lo, points)];
            uint index = (vertices & 0xffffu) + bitCount((vertices >> 16) & ((1u << axis) - 1u));
            if (t < 3u * triangle_count) {
                atomicOr(s_index_words[t >> 2], (index & 255u) << ((t & 3u) * 8u));
            }
        }
    }
    barrier();
    uint words = (triangle_count + 3u) / 4u * 3u;
    for (uint w = me; w < words; w += MESHLET_WORKGROUP) {
        local_index_words[first_triangle / 4u * 3u + w] = s_index_words[w];
    }
    if (me == 0u) {
        vec3 lo_all = uintBitsToFloat(uvec3(s_aabb_min[0], s_aabb_min[1], s_aabb_min[2]));
        vec3 hi_all = uintBitsToFloat(uvec3(s_aabb_max[0], s_aabb_max[1], s_aabb_max[2]));
        meshlets[payload.base_meshlet + s] = meshlet_new(first_vertex, vertex_count,
            first_triangle, triangle_count, lo_all, hi_all, lo, size);
    }
}
