#version 460
// The compute path of the PMB draw: one workgroup per block of the extraction tests its box
// against the frustum and, when it passes, writes its triangles in clip space with their
// shading attributes into the frame's list for the shared compute rasterizer, as the meshlet
// draw's compute path does. Slots past the list's capacity are dropped; the drawn-triangle
// counter stays exact, so the host sees the overflow.
#extension GL_EXT_shader_16bit_storage : require
#include "raster/raster.glsl"
#include "common/grid_world.glsl"
#include "iso/direct/attributes.glsl"
#include "iso/meshlet_draw/params.glsl"
#include "iso/meshlet_draw/corner.glsl"
#include "iso/pmb/format.glsl"
#include "iso/pmb_draw/blocks.glsl"

layout(binding = 3) readonly buffer Positions { float positions[]; };
layout(binding = 4) readonly buffer Normals { float normals[]; };
layout(binding = 5) readonly buffer Indices { uint16_t indices[]; };

#define SURFACE_LIST_BINDING 6
#include "iso/meshlet_draw/list.glsl"

layout(local_size_x = 32) in;

shared uint base;
shared uint kept;

void main() {
    uint id = pmb_draw_group();
    // Both tests are the same for the whole workgroup, so it leaves together.
    if (id >= block_count) {
        return;
    }
    PmbBlock b = descriptors[id];
    if (!pmb_block_in_frustum(b)) {
        return;
    }
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        uint first = atomicAdd(triangles_drawn, b.triangle_count);
        atomicAdd(blocks_drawn, 1u);
        base = first;
        kept = reserve_list_slots(first, b.triangle_count);
    }
    barrier();
    for (uint t = me; t < kept; t += 32u) {
        for (uint j = 0u; j < 3u; ++j) {
            uint v = 3u * (b.first_vertex + uint(indices[b.first_index + 3u * t + j]));
            write_list_corner(base + t, j,
                              surface_corner(vec3(positions[v], positions[v + 1u], positions[v + 2u]),
                                             vec3(normals[v], normals[v + 1u], normals[v + 2u])),
                              id);
        }
    }
}
