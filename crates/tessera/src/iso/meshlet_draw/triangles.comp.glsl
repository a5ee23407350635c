#version 460
// The compute path of the meshlet draw: one workgroup per meshlet tests its box against the
// frustum and, when it passes, writes its triangles in clip space with their shading
// attributes into the frame's list for the shared compute rasterizer. Slots past the list's
// capacity are dropped; the drawn-triangle counter stays exact, so the host sees the overflow.
//
// With OCCLUSION_PASS defined it is one pass of occlusion culling (iso/meshlet_draw/occlusion.rs):
// 1 draws the meshlets that owned a pixel last frame, 2 those it did not draw whose box the
// max-depth pyramid of pass 1's frame does not hide. Each triangle carries its meshlet's id
// for the resolve, which flags the meshlets owning pixels.
#include "raster/raster.glsl"
#include "common/grid_world.glsl"
#include "iso/direct/attributes.glsl"
#include "iso/meshlet_draw/params.glsl"
#include "iso/meshlet_draw/buffers.glsl"
#include "iso/meshlet_draw/corner.glsl"

#define SURFACE_LIST_BINDING 6
#include "iso/meshlet_draw/list.glsl"

layout(local_size_x = 32) in;
#ifdef OCCLUSION_PASS
// Per meshlet: bit 0 owned a pixel in the last frame, bit 1 drawn in this frame's pass 1.
layout(binding = 9) buffer MeshletFlags { uint meshlet_flags[]; };
#if OCCLUSION_PASS == 2
layout(binding = 10) readonly buffer Hzb { float hzb[]; };
#include "raster/hzb.glsl"
#include "raster/hzb_test.glsl"
#endif
#endif

// Whether this pass draws meshlet `id`.
bool meshlet_drawn_here(uint id, Meshlet m) {
#if !defined(OCCLUSION_PASS)
    return meshlet_in_frustum(m);
#elif OCCLUSION_PASS == 1
    bool seen = (meshlet_flags[id] & 1u) != 0u;
    barrier();  // every invocation has read the flags before the first one rewrites them
    bool drawn = seen && meshlet_in_frustum(m);
    if (gl_LocalInvocationIndex == 0u) {
        meshlet_flags[id] = drawn ? 2u : 0u;
    }
    return drawn;
#else
    vec3 lo;
    vec3 hi;
    if ((meshlet_flags[id] & 2u) != 0u || !meshlet_in_frustum(m)) {
        return false;
    }
    uvec2 size = uvec2(params.frame_width, params.frame_height);
    return !meshlet_box(m, lo, hi)
        || hzb_box_may_be_visible(params.grid_to_clip, lo, hi, size, hzb_level_count(size));
#endif
}

shared uint base;
shared uint kept;

void main() {
    uint id = meshlet_group();
    // Both tests are the same for the whole workgroup, so it leaves together.
    if (id >= meshlets_to_draw()) {
        return;
    }
    Meshlet m = meshlets[id];
    if (!meshlet_drawn_here(id, m)) {
        return;
    }
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        uint first = atomicAdd(triangles_drawn, meshlet_triangle_count(m));
        atomicAdd(meshlets_drawn, 1u);
        base = first;
        kept = reserve_list_slots(first, meshlet_triangle_count(m));
    }
    barrier();
    for (uint t = me; t < kept; t += 32u) {
        uint slot = base + t;
        for (uint j = 0u; j < 3u; ++j) {
            uint v = m.vertex_offset + meshlet_local_index(3u * (m.triangle_offset + t) + j);
            write_list_corner(slot, j, surface_corner(meshlet_position(v), meshlet_normal(v)), id);
        }
    }
}
