#version 460
// PMB extraction (Liu et al.; paper C §3.1): one workgroup per occupied block. Every sample
// of the block's closed box owns the crossed edges from it along +x, +y and +z that lie in
// the box (common/mc_edges.glsl): the core cells' own, and on the max faces those of the
// padding layer. Each owned crossed edge becomes one vertex, numbered by a prefix sum over
// the box's samples (x fastest; x, y, z edge each), and each occupied core cell's triangles
// look their vertices up in shared memory, so the block's index run has 16-bit indices and
// no vertex twice.
//
// By default invocations take runs of consecutive samples rather than one sample each, so the
// workgroup stays within the 128 invocations every device accepts (an 8×8×8 block's box has
// 729); with PMB_WORKGROUP = the box's samples, each takes one, as Liu et al. launch it.
// A block reserves its output with one atomic per total; a reservation that passes the
// capacities writes nothing, while the totals keep counting, so the host grows the buffers
// and extracts again.
#extension GL_EXT_shader_16bit_storage : require
#if PMB_SUBGROUP_SCAN
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
#include "common/volume.glsl"
#include "common/ablation.glsl"
#include "common/exact.glsl"
#include "common/mc_tables.glsl"
#include "common/mc_cell.glsl"
#include "common/mc_vertex.glsl"
#include "common/mc_edges.glsl"
#include "iso/direct/block_list.glsl"
#include "iso/pmb/params.glsl"
#include "iso/pmb/format.glsl"

layout(local_size_x = PMB_WORKGROUP) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) readonly buffer Blocks { BlockListHeader block_header; uint occupied_blocks[]; };
layout(binding = 2) coherent buffer Counters { PmbCounters counters; };
layout(binding = 3) writeonly buffer Descriptors { PmbBlock descriptors[]; };
layout(binding = 4) writeonly buffer Positions { float positions[]; };
layout(binding = 5) writeonly buffer Normals { float normals[]; };
layout(binding = 6) writeonly buffer Indices { uint16_t indices[]; };

const uint PMB_BOX_POINTS = (PMB_BLOCK_X + 1u) * (PMB_BLOCK_Y + 1u) * (PMB_BLOCK_Z + 1u);
const uint PMB_RUN = (PMB_BOX_POINTS + PMB_WORKGROUP - 1u) / PMB_WORKGROUP;
const uint PMB_NO_ROW = 0xffffffffu;

// Per sample of the box: its owned crossed edges (bits 0-2: x, y, z), then, once numbered,
// the local vertex of the first of them (bits 3 and up).
shared uint s_point_edges[PMB_BOX_POINTS];
// Per sample: the table row of the core cell whose minimum corner it is, PMB_NO_ROW where
// that is no occupied core cell.
shared uint s_point_row[PMB_BOX_POINTS];
// The block's first vertex and first triangle in the output; whether it fits.
shared uint s_reserved[3];

// The runs' prefix sums: any order of the prefixes among the invocations gives each vertex
// and triangle of the block one slot, so the scan's order is not checked.
#define WORKGROUP_SCAN_SIZE PMB_WORKGROUP
#define WORKGROUP_SCAN_SUBGROUPS PMB_SUBGROUP_SCAN
#include "common/workgroup_scan.glsl"

void main() {
    uint listed = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (listed >= block_header.count) {
        return;  // the last row of a 2-D grid; uniform across the workgroup
    }
    uint me = gl_LocalInvocationIndex;
    float iso = params.isovalue;
    uvec3 dims = params.volume_dims;
    uvec3 block = pmb_block_of(occupied_blocks[listed]);
    uvec3 lo = block * PMB_BLOCK;
    uvec3 hi = mc_box_end(lo, PMB_BLOCK, dims);
    uvec3 points = hi - lo + 1u;
    uint run_first = min(me * PMB_RUN, points.x * points.y * points.z);
    uint run_end = min(run_first + PMB_RUN, points.x * points.y * points.z);

    // Classification: owned crossed edges of every sample, table rows of the core cells.
    uint vertices = 0u;
    uint triangles = 0u;
    for (uint j = run_first; j < run_end; ++j) {
        uvec3 p = mc_box_point(lo, points, j);
        uint owned = mc_box_owned_crossings(volume_tex, p, hi, iso);
        uint row = PMB_NO_ROW;
        if (all(lessThan(p, hi))) {
            uint case_index = mc_cell_case(volume_tex, p, iso);
            if (MC_EDGE_MASK[case_index] != 0u) {
                row = mc_cell_row(volume_tex, p, case_index, iso);
                triangles += mc_tri_count(row);
            }
        }
        vertices += bitCount(owned);
        s_point_edges[j] = owned;
        s_point_row[j] = row;
    }
    uvec3 totals;
    uvec3 before = workgroup_exclusive_scan(uvec3(vertices, triangles, 0u), totals);
    if (me == 0u) {
        uint vertex_total = totals.x;
        uint triangle_total = totals.y;
        s_reserved[2] = 0u;
        if (triangle_total > 0u) {
            uint first_vertex = atomicAdd(counters.vertices, vertex_total);
            uint first_triangle = atomicAdd(counters.triangles, triangle_total);
            bool fits = first_vertex + vertex_total <= params.vertex_capacity
                && first_triangle + triangle_total <= params.triangle_capacity;
            if (fits) {
                descriptors[atomicAdd(counters.blocks, 1u)] = PmbBlock(
                    uint[3](block.x, block.y, block.z), first_vertex, vertex_total,
                    3u * first_triangle, triangle_total);
            } else {
                atomicOr(counters.overflow, 1u);
            }
            s_reserved[0] = first_vertex;
            s_reserved[1] = first_triangle;
            s_reserved[2] = uint(fits);
        }
    }
    barrier();
    if (s_reserved[2] == 0u) {
        return;  // no surface, or no room: uniform across the workgroup
    }

    // Vertices: each run numbers its samples' edges from its prefix.
    uint local = before.x;
    for (uint j = run_first; j < run_end; ++j) {
        uint owned = s_point_edges[j];
        s_point_edges[j] = owned | local << 3;
        uvec3 p = mc_box_point(lo, points, j);
        // Over the set bits rather than the three axes: a loop the compiler cannot unroll,
        // so the vertex arithmetic is compiled once (llvmpipe takes minutes per copy).
        for (; owned != 0u; owned &= owned - 1u) {
            uint axis = findLSB(owned);
            vec3 position;
            vec3 normal;
            if (!ablation_stands_in_for_vertex(p, position, normal)) {
                mc_exact_edge_vertex(volume_tex, p, axis, iso, dims, position, normal);
            }
            uint v = s_reserved[0] + local;
            for (uint a = 0u; a < 3u; ++a) {
                positions[3u * v + a] = position[a];
                normals[3u * v + a] = normal[a];
            }
            local += 1u;
        }
    }
    barrier();

    // Triangles: each edge's vertex is its owner's first plus the owner's crossed edges
    // along the axes before it.
    uint index = 3u * (s_reserved[1] + before.y);
    for (uint j = run_first; j < run_end; ++j) {
        uint row = s_point_row[j];
        if (row == PMB_NO_ROW) {
            continue;
        }
        uvec3 cell = mc_box_point(lo, points, j);
        for (uint i = 0u; i < 3u * mc_tri_count(row); ++i, ++index) {
            uvec3 start;
            uint axis;
            mc_edge_owner(cell, mc_tri_edge(row, i), start, axis);
            uvec3 d = start - lo;
            uint owner = s_point_edges[(d.z * points.y + d.y) * points.x + d.x];
            uint before = bitCount(owner & ((1u << axis) - 1u));
            indices[index] = uint16_t((owner >> 3) + before);
        }
    }
}
