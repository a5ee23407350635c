#version 460
// Task stage of direct isosurface rasterization (paper D, §3.4.1): one workgroup per block of
// BLOCK_X×BLOCK_Y×BLOCK_Z cells. Skips blocks the min-max grid rules out, classifies the cells,
// compacts the occupied ones and cuts them into lists for mesh workgroups. The paper's warp
// ballots become shared-memory counts so any subgroup size works.
#extension GL_EXT_mesh_shader : require
#include "common/volume.glsl"
#include "common/mc_tables.glsl"
#include "common/mc_cell.glsl"
#include "iso/direct/block_list.glsl"
#include "iso/direct/payload.glsl"
#include "iso/direct/params.glsl"

layout(local_size_x = 32) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) readonly buffer Nodes { vec2 minmax_nodes[]; };
#if BLOCK_LIST
#include "iso/direct/cell_box_record.glsl"
// With occlusion culling, task workgroups take their blocks from a list (linear block ids).
layout(binding = 4) readonly buffer Blocks { BlockListHeader block_header; uint block_list[]; };
// Per block, the box of its cells that made triangles (iso/direct/cell_box.glsl) and the bits
// of the isovalue it was made at: the proxy quads of later frames cover only these cells.
layout(binding = 5) writeonly buffer CellBoxes { uvec2 cell_boxes[]; };
#endif

taskPayloadSharedEXT TaskPayload payload;

const uint CELLS = BLOCK_X * BLOCK_Y * BLOCK_Z;
const uint PER_THREAD = CELLS / 32u;
shared uint vertex_counts[CELLS];
shared uint occupied_per_thread[32];
shared uint occupied_ids[CELLS];
shared uint list_count;

// Fills the payload with `block`'s occupied cells cut into mesh-workgroup lists; returns how
// many lists. Every invocation calls it (it has barriers).
uint block_lists(uvec3 block, uvec3 dims, float iso) {
    uint me = gl_LocalInvocationIndex;
#if BLOCK_LIST
    cell_box_record_begin();
    barrier();
#endif
    // Each invocation owns PER_THREAD consecutive cell ids, so compaction keeps id order.
    uint occupied = 0u;
    uvec3 occupied_lo = uvec3(0xffffffffu);  // the box of this invocation's occupied cells
    uvec3 occupied_hi = uvec3(0u);
    for (uint k = 0u; k < PER_THREAD; ++k) {
        uint id = me * PER_THREAD + k;
        uvec3 local = uvec3(id % BLOCK_X, (id / BLOCK_X) % BLOCK_Y, id / (BLOCK_X * BLOCK_Y));
        uvec3 cell = block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + local;
        uint count = 0u;
        if (all(lessThan(cell, dims - 1u))) {
            uint c = mc_cell_case(volume_tex, cell, iso);
            // Vertices are per crossing edge whatever the ambiguous faces decide; the
            // triangles (at most vertices - 2 per cell) then fit DIRECT_MAX_TRIANGLES.
            count = bitCount(MC_EDGE_MASK[c]);
        }
        vertex_counts[id] = count;
        if (count > 0u) {
            occupied += 1u;
            occupied_lo = min(occupied_lo, local);
            occupied_hi = max(occupied_hi, local);
        }
    }
#if BLOCK_LIST
    if (occupied > 0u) {
        cell_box_record_add(occupied_lo, occupied_hi);
    }
#endif
    occupied_per_thread[me] = occupied;
    barrier();

    uint first = 0u;
    for (uint t = 0u; t < me; ++t) {
        first += occupied_per_thread[t];
    }
    uint slot = first;
    for (uint k = 0u; k < PER_THREAD; ++k) {
        uint id = me * PER_THREAD + k;
        if (vertex_counts[id] > 0u) {
            occupied_ids[slot] = id;
            slot += 1u;
        }
    }
    barrier();
    for (uint w = me; w < CELLS / 4u; w += 32u) {
        uint word = 0u;
        for (uint b = 0u; b < 4u; ++b) {
            word |= (occupied_ids[4u * w + b] & 255u) << (8u * b);
        }
        payload.cell_words[w] = word;
    }

    // One invocation cuts the compact list into mesh-workgroup lists; it is short (≤ 256).
    if (me == 0u) {
        uint total = 0u;
        for (uint t = 0u; t < 32u; ++t) {
            total += occupied_per_thread[t];
        }
        uint lists = 0u;
        uint start = 0u;
        uint cells = 0u;
        uint vertices = 0u;
        for (uint i = 0u; i < total; ++i) {
            uint n = vertex_counts[occupied_ids[i]];
            if (cells == DIRECT_MAX_CELLS || vertices + n > DIRECT_MAX_VERTICES) {
                payload.lists[lists++] = start | (cells << 16);
                start = i;
                cells = 0u;
                vertices = 0u;
            }
            cells += 1u;
            vertices += n;
        }
        if (cells > 0u) {
            payload.lists[lists++] = start | (cells << 16);
        }
        payload.block = block;
        list_count = lists;
    }
    barrier();
    return list_count;
}

void main() {
    uvec3 dims = params.dims.xyz;
    float iso = params.isovalue;
    uvec3 block_dims = (dims - 2u) / uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + 1u;
#if BLOCK_LIST
    uint listed = block_list[gl_WorkGroupID.x];
    uvec3 block = uvec3(listed % block_dims.x, (listed / block_dims.x) % block_dims.y,
                        listed / (block_dims.x * block_dims.y));
#else
    uvec3 block = gl_WorkGroupID;
#endif
    vec2 range = minmax_nodes[block.x + block_dims.x * (block.y + block_dims.y * block.z)];
    // The same for the whole workgroup, so block_lists' barriers stay in uniform control
    // flow. One EmitMeshTasksEXT, at the end (an early one for empty blocks is what made
    // NVIDIA's driver emit meshlet extraction blocks twice; docs/BENCHMARKS.md, run 44).
    uint lists = 0u;
    if (range.x <= iso && iso <= range.y) {
        lists = block_lists(block, dims, iso);
#if BLOCK_LIST
        // A cell with a crossing edge makes triangles, so a block makes triangles exactly when
        // it has lists.
        if (gl_LocalInvocationIndex == 0u) {
            cell_boxes[listed] = uvec2(cell_box_recorded(lists > 0u), floatBitsToUint(iso));
        }
#endif
    }
    EmitMeshTasksEXT(lists, 1, 1);
}
