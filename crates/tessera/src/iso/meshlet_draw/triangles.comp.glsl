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

layout(local_size_x = 32) in;
layout(binding = 6) writeonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = 7) writeonly buffer Attributes { TriangleAttributes attributes[]; };
// raster::RasterCounts: triangles in the list, then the rasterizer's dispatch arguments.
layout(binding = 8) buffer Counts { uint triangle_count; uint dispatch[3]; };

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
        uint capacity = params.triangle_capacity;
        uint fit = first >= capacity ? 0u : min(m.triangle_count, capacity - first);
        atomicAdd(triangle_count, fit);
        base = first;
        kept = fit;
    }
    barrier();
    vec3 grid_to_world = params.grid_to_world.xyz;
    for (uint t = me; t < kept; t += 32u) {
        uint slot = base + t;
        for (uint j = 0u; j < 3u; ++j) {
            uint v = m.vertex_offset + meshlet_local_index(3u * (m.triangle_offset + t) + j);
            vec3 p = meshlet_position(v);
            triangles[slot].clip[j] = params.grid_to_clip * vec4(p, 1.0);
            attributes[slot].normal_world[j] = vec4(grid_normal_to_world(meshlet_normal(v), grid_to_world), 0.0);
            attributes[slot].position_world[j] = vec4(grid_point_to_world(p, params.dims, grid_to_world), 1.0);
        }
    }
}
