#version 460
// Binned compute path of interval shading, scatter: one invocation per entry of the counting
// pass writes its tet into its tile's list, at the tile's running end (`tile_bins` holds each
// tile's start after the scan, and each tile's end after this pass).
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#endif

layout(local_size_x = BIN_SCATTER_WORKGROUP) in;

#include "tet/interval/buffers.glsl"
#include "tet/interval/params.glsl"
#include "tet/interval/compute_buffers.glsl"
#include "tet/interval/bin_buffers.glsl"

void main() {
    // Workgroups on a 2-D grid past the device's row limit (IndirectArgs).
    uint e = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * uint(BIN_SCATTER_WORKGROUP) + gl_LocalInvocationIndex;
    if (e >= min(bin_entry_count, uint(bin_entries.length()))) {
        return;
    }
    uvec2 entry = bin_entries[e];
    if (entry.x != NO_TET) {
        bin_list[atomicAdd(tile_bins[entry.y], 1u)] = entry.x;
    }
}
