// The frame's triangle list a compute-path draw of a stored surface (meshlets, PMB blocks)
// writes for the shared compute rasterizer, in three bindings from SURFACE_LIST_BINDING (the
// including shader defines it past its own): clip-space triangles, their shading attributes
// (iso/direct/attributes.glsl, shaded by direct's resolve) and raster::RasterCounts, whose
// dispatch arguments grow as slots are reserved (zero before the pass). Needs
// raster/raster.glsl, iso/direct/attributes.glsl and iso/meshlet_draw/corner.glsl.

#include "common/indirect_args.glsl"

layout(binding = SURFACE_LIST_BINDING) writeonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = SURFACE_LIST_BINDING + 1) writeonly buffer Attributes { TriangleAttributes attributes[]; };
// Triangles in the list, then the rasterizer's dispatch arguments.
layout(binding = SURFACE_LIST_BINDING + 2) buffer Counts { uint triangle_count; uint dispatch[3]; };

// Corner `j` of the triangle in `slot`, made by `maker` (a meshlet or block id the resolve
// flags as seen under occlusion culling; iso/direct/attributes.glsl).
void write_list_corner(uint slot, uint j, SurfaceCorner c, uint maker) {
    triangles[slot].clip[j] = c.clip;
    attributes[slot].corners[j] = CornerAttributes(c.normal_world, maker);
}

// Reserves the list's slots of `count` triangles after `first` more were drawn (counted
// exactly by the caller, so the host sees an overflow): how many fit.
uint reserve_list_slots(uint first, uint count) {
    uint capacity = params.triangle_capacity;
    uint fit = first >= capacity ? 0u : min(count, capacity - first);
    if (fit > 0u) {
        atomicAdd(triangle_count, fit);
        GROW_INDIRECT_ARGS3(dispatch, first + fit, RASTER_GROUP_SIZE);
    }
    return fit;
}
