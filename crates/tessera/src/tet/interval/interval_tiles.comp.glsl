#version 460
// Compute path of interval shading, tile pass: one workgroup per TILE × TILE-pixel tile of a
// large tet's screen rectangle (interval_raster.comp.glsl allots them), one invocation per
// pixel. The first invocation remakes the tet's proxies for the whole workgroup.
#extension GL_EXT_shader_atomic_float : require
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif

layout(local_size_x = TILE, local_size_y = TILE) in;

#include "tet/interval/pixel_passes.glsl"

shared ProxyRaster tet_proxy[3];
shared uint tet_proxy_count;

void main() {
    // Workgroups on a 2-D grid past the device's row limit (IndirectArgs).
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    // Uniform per workgroup, so returning before the barrier is allowed.
    if (tile >= min(tile_count, uint(TILE_CAPACITY)) || tile_owner[tile] == NO_TET) {
        return;
    }
    uvec4 tiled = tiled_tets[tile_owner[tile]];
    if (gl_LocalInvocationIndex == 0u) {
        Proxy proxies[3];
        bool clipped;
        tet_proxy_count = tet_proxies(tiled.x, proxies, clipped);
        for (uint k = 0u; k < 3u; ++k) {
            tet_proxy[k] = proxy_raster(proxies[k]);
        }
    }
    barrier();
    uint index = tile - tiled.y;
    uvec2 first = uvec2(tiled.z & 0xffffu, tiled.z >> 16);
    uvec2 pixel = first + uvec2(index % tiled.w, index / tiled.w) * uint(TILE) + gl_LocalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.counts.yz))) {
        return;
    }
    for (uint k = 0u; k < tet_proxy_count; ++k) {
        shade_pixel(tet_proxy[k], pixel, tiled.x);
    }
}
