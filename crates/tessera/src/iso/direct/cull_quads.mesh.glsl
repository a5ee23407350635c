#version 460
// One screen-space quad per occupied region at the region's nearest depth (paper D, §3.5.2):
// where any of its fragments survives the depth test against the geometry drawn so far, the
// region may be visible. Regions reaching the near plane are flagged visible outright. The
// region's box is that of its blocks whose (min, max) holds the isovalue, each narrowed to the
// cells that made triangles when it was last extracted at this isovalue (cell_box.glsl).
#extension GL_EXT_mesh_shader : require
#include "iso/direct/params.glsl"
#include "iso/direct/cull.glsl"
#include "iso/direct/block_list.glsl"
#include "iso/direct/cell_box.glsl"

layout(local_size_x = 32) in;
layout(triangles, max_vertices = 128, max_primitives = 64) out;
layout(binding = 0) readonly buffer Occupied { BlockListHeader occupied_list; uint occupied[]; };
layout(binding = 1) writeonly buffer Visible { uint visible[]; };
layout(binding = 2) readonly buffer Nodes { vec2 minmax_nodes[]; };
// Per block, its recorded cell box and the isovalue's bits (cell_box.glsl).
layout(binding = 3) readonly buffer CellBoxes { uvec2 cell_boxes[]; };

layout(location = 0) flat out uint region_id[];

shared uint quad_slots[33];

// The grid range (first and last sample) the region's surface may lie in; empty (lo > hi) when
// no block of it holds the isovalue.
void region_range(uint region, uvec3 dims, out uvec3 lo, out uvec3 hi) {
    lo = uvec3(0xffffffffu);
    hi = uvec3(0u);
    float iso = params.isovalue;
    uvec3 block_cells = uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    for (uint h = 0u; h < 2u; ++h) {
        uint block = cull_region_block(region, h, dims);
        if (block == ~0u) {
            continue;
        }
        vec2 range = minmax_nodes[block];
        if (iso < range.x || iso > range.y) {
            continue;
        }
        uvec3 block_lo = cull_region_coords(region, dims) * REGION_CELLS + uvec3(0u, 0u, h * BLOCK_Z);
        uvec3 block_hi = min(block_lo + block_cells, dims - 1u);
        cell_box_narrow(cell_boxes[block], iso, block_lo, block_hi);
        lo = min(lo, block_lo);
        hi = max(hi, block_hi);
    }
}

void main() {
    uint me = gl_LocalInvocationIndex;
    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 32u + me;
    uvec3 dims = params.dims.xyz;
    bool has_quad = false;
    uint region = 0u;
    vec3 lo_ndc = vec3(1e30);
    vec3 hi_ndc = vec3(-1e30);
    if (i < occupied_list.count) {
        region = occupied[i];
        uvec3 lo;
        uvec3 hi;
        region_range(region, dims, lo, hi);
        bool crosses_near = false;
        for (uint c = 0u; c < 8u; ++c) {
            vec3 p = mix(vec3(lo), vec3(hi), vec3(c & 1u, (c >> 1) & 1u, c >> 2));
            vec4 clip = params.grid_to_clip * vec4(p, 1.0);
            if (clip.w <= 1e-6 || clip.z < 0.0) {
                crosses_near = true;
            } else {
                vec3 ndc = clip.xyz / clip.w;
                lo_ndc = min(lo_ndc, ndc);
                hi_ndc = max(hi_ndc, ndc);
            }
        }
        if (crosses_near) {
            visible[region] = 1u;
        } else {
            has_quad = true;
        }
    }
    quad_slots[me + 1u] = uint(has_quad);
    barrier();
    if (me == 0u) {
        quad_slots[0] = 0u;
        for (uint t = 1u; t <= 32u; ++t) {
            quad_slots[t] += quad_slots[t - 1u];
        }
    }
    barrier();
    uint quads = quad_slots[32];
    SetMeshOutputsEXT(quads * 4u, quads * 2u);
    if (has_quad) {
        uint q = quad_slots[me];
        float z = max(lo_ndc.z, 0.0);
        for (uint k = 0u; k < 4u; ++k) {
            vec2 xy = vec2((k & 1u) != 0u ? hi_ndc.x : lo_ndc.x, (k & 2u) != 0u ? hi_ndc.y : lo_ndc.y);
            gl_MeshVerticesEXT[4u * q + k].gl_Position = vec4(xy, z, 1.0);
            region_id[4u * q + k] = region;
        }
        gl_PrimitiveTriangleIndicesEXT[2u * q] = uvec3(4u * q, 4u * q + 1u, 4u * q + 2u);
        gl_PrimitiveTriangleIndicesEXT[2u * q + 1u] = uvec3(4u * q + 1u, 4u * q + 3u, 4u * q + 2u);
    }
}
