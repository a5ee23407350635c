#version 460
// The compute path of the meshlet draw: one workgroup per meshlet tests its box against the
// frustum and, when it passes, writes its triangles in clip space with their shading
// attributes into the frame's list for the shared compute rasterizer. Slots past the list's
// capacity are dropped; the drawn-triangle counter stays exact, so the host sees the overflow.
#include "raster/raster.glsl"
#include "common/grid_world.glsl"
#include "iso/direct/attributes.glsl"
#include "iso/meshlet_draw/params.glsl"
#include "iso/meshlet_draw/buffers.glsl"
#include "iso/meshlet_draw/corner.glsl"

#define SURFACE_LIST_BINDING 6
#include "iso/meshlet_draw/list.glsl"

layout(local_size_x = 32) in;

shared uint base;
shared uint kept;

void main() {
    uint id = meshlet_group();
    // Both tests are the same for the whole workgroup, so it leaves together.
    if (id >= meshlets_to_draw()) {
        return;
    }
    Meshlet m = meshlets[id];
    if (!meshlet_in_frustum(m)) {
        return;
    }
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        uint first = atomicAdd(triangles_drawn, m.triangle_count);
        atomicAdd(meshlets_drawn, 1u);
        base = first;
        kept = reserve_list_slots(first, m.triangle_count);
    }
    barrier();
    for (uint t = me; t < kept; t += 32u) {
        uint slot = base + t;
        for (uint j = 0u; j < 3u; ++j) {
            uint v = m.vertex_offset + meshlet_local_index(3u * (m.triangle_offset + t) + j);
            write_list_corner(slot, j, surface_corner(meshlet_position(v), meshlet_normal(v)));
        }
    }
}
