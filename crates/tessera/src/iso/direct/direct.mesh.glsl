#version 460
// Mesh stage of direct isosurface rasterization (paper D, §3.4.2): one invocation per cell of
// the workgroup's list runs marching cubes and writes its vertices and triangles at offsets
// from a shared-memory scan. Vertices are per cell (not shared across cells), as in the paper.
#extension GL_EXT_mesh_shader : require
#if MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#include "common/volume.glsl"
#include "common/mc_tables.glsl"
#include "common/mc_cell.glsl"
#include "common/grid_world.glsl"
#include "iso/direct/payload.glsl"
#include "iso/direct/params.glsl"

layout(local_size_x = 32) in;
layout(triangles, max_vertices = DIRECT_MAX_VERTICES, max_primitives = DIRECT_MAX_TRIANGLES) out;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 2) buffer Stats { uint stats[]; };           // [mesh workgroups, triangles, vertices]
layout(binding = 3) buffer Capture { uint captured; float capture_xyz[]; };

#include "iso/direct/views.glsl"

layout(location = 0) out vec3 normal_world[];
layout(location = 1) out vec3 position_world[];

taskPayloadSharedEXT TaskPayload payload;

shared uint vertex_offsets[33];
shared uint triangle_offsets[33];

void main() {
    uint me = gl_LocalInvocationIndex;
    uint list = payload.lists[gl_WorkGroupID.x];
    uint cell_count = list >> 16;
    uvec3 dims = params.dims.xyz;
    float iso = params.isovalue;

    uint case_index = 0u;
    uint row = 0u;  // case 0's row: no triangles
    uvec3 cell = uvec3(0u);
    if (me < cell_count) {
        uint i = (list & 0xffffu) + me;
        uint id = (payload.cell_words[i >> 2] >> ((i & 3u) * 8u)) & 255u;
        uvec3 local = uvec3(id % BLOCK_X, (id / BLOCK_X) % BLOCK_Y, id / (BLOCK_X * BLOCK_Y));
        cell = payload.block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + local;
        case_index = mc_cell_case(volume_tex, cell, iso);
        row = mc_cell_row(volume_tex, cell, case_index, iso);
    }
    uint edges = MC_EDGE_MASK[case_index];
    uint triangles = mc_tri_count(row);
    vertex_offsets[me + 1u] = bitCount(edges);
    triangle_offsets[me + 1u] = triangles;
    barrier();
    if (me == 0u) {
        vertex_offsets[0] = 0u;
        triangle_offsets[0] = 0u;
        for (uint t = 1u; t <= 32u; ++t) {
            vertex_offsets[t] += vertex_offsets[t - 1u];
            triangle_offsets[t] += triangle_offsets[t - 1u];
        }
    }
    barrier();
    uint vertex_total = vertex_offsets[32];
    uint triangle_total = triangle_offsets[32];
    SetMeshOutputsEXT(vertex_total, triangle_total);

    uint v0 = vertex_offsets[me];
    for (uint e = 0u; e < 12u; ++e) {
        if ((edges & (1u << e)) == 0u) {
            continue;
        }
        vec3 p;
        vec3 n;
        mc_edge_vertex(volume_tex, cell, e, iso, dims, p, n);
        uint v = v0 + bitCount(edges & ((1u << e) - 1u));
        gl_MeshVerticesEXT[v].gl_Position = view_grid_to_clip() * vec4(p, 1.0);
        normal_world[v] = grid_normal_to_world(n, params.grid_to_world.xyz);
        position_world[v] = grid_point_to_world(p, dims, params.grid_to_world.xyz);
    }
    uint t0 = triangle_offsets[me];
    for (uint k = 0u; k < triangles; ++k) {
        uvec3 tri;
        for (uint j = 0u; j < 3u; ++j) {
            uint e = mc_tri_edge(row, 3u * k + j);
            tri[j] = v0 + bitCount(edges & ((1u << e) - 1u));
        }
        gl_PrimitiveTriangleIndicesEXT[t0 + k] = tri;
        if (params.triangle_capacity != 0u) {
            // Debug capture of the grid-space triangle, for tests against the CPU reference.
            // The count goes on past the capacity, so an
            // overflow is seen rather than silently truncated.
            uint slot = atomicAdd(captured, 1u);
            if (slot >= params.triangle_capacity) {
                continue;
            }
            for (uint j = 0u; j < 3u; ++j) {
                vec3 p;
                vec3 n;
                mc_edge_vertex(volume_tex, cell, mc_tri_edge(row, 3u * k + j), iso, dims, p, n);
                capture_xyz[slot * 9u + 3u * j + 0u] = p.x;
                capture_xyz[slot * 9u + 3u * j + 1u] = p.y;
                capture_xyz[slot * 9u + 3u * j + 2u] = p.z;
            }
        }
    }
    if (me == 0u) {
        atomicAdd(stats[0], 1u);
        atomicAdd(stats[1], triangle_total);
        atomicAdd(stats[2], vertex_total);
    }
}
