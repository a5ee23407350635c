#version 460
// Compute path of interval shading, first pass: one invocation per tet makes the mesh shader's
// proxies (tet/interval/proxy.glsl). A tet whose screen rectangle holds at most
// `params.counts.w` pixels is drawn here, pixel by pixel; a larger one is handed to the tile
// pass (interval_tiles.comp.glsl) as TILE × TILE-pixel tiles, one workgroup each, so that the
// few huge proxies near the eye do not leave one invocation walking a whole screen. Where the
// tile buffers are full, the tet is drawn here after all (slowly, but correctly).
#extension GL_EXT_shader_atomic_float : require
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif

layout(local_size_x = 64) in;

#include "tet/interval/buffers.glsl"
#include "tet/interval/params.glsl"
#include "tet/interval/compute_buffers.glsl"
#include "tet/interval/proxy.glsl"
#include "tet/interval/length.glsl"
#include "tet/interval/table.glsl"
#include "tet/interval/integrand.glsl"
#if INTEGRAND == INTEGRAND_SDF
#include "tet/interval/sdf.glsl"
#endif
#include "tet/interval/splat.glsl"

// Hands the tet to the tile pass; false when the buffers are full.
bool hand_to_tiles(uint tet, uvec2 first, uvec2 last) {
    uvec2 tiles = (last - first) / uint(TILE) + 1u;
    uint count = tiles.x * tiles.y;
    uint slot = atomicAdd(stats[STAT_TILED], 1u);
    if (slot >= TILED_CAPACITY) {
        return false;
    }
    uint first_tile = atomicAdd(tile_count, count);
    uint end = min(first_tile + count, uint(TILE_CAPACITY));
    bool fits = first_tile + count <= TILE_CAPACITY && first_tile + count >= first_tile;
    uint owner = fits ? slot : NO_TET;
    for (uint t = first_tile; t < end; ++t) {
        tile_owner[t] = owner;
    }
    if (fits) {
        tiled_tets[slot] = uvec4(tet, first_tile, first.x | (first.y << 16), tiles.x);
    }
    return fits;
}

void main() {
    // Workgroups spread over x and y past 65,535 (tessera_gpu::spread_groups).
    uint tet = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    if (tet >= params.counts.x) {
        return;
    }
    Proxy proxies[3];
    bool clipped;
    uint n = tet_proxies(tet, proxies, clipped);
    if (clipped) {
        atomicAdd(stats[STAT_CLIPPED], 1u);
    }
    // Pixels whose centres the proxies' screen rectangle holds.
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    for (uint k = 0u; k < n; ++k) {
        for (uint j = 0u; j <= proxies[k].silhouette && proxies[k].silhouette > 0u; ++j) {
            vec2 s = to_screen(proxies[k].p[j]);
            lo = min(lo, s);
            hi = max(hi, s);
        }
    }
    vec2 size = vec2(params.counts.yz);
    vec2 first_f = max(ceil(lo - 0.5), vec2(0.0));
    vec2 last_f = min(floor(hi - 0.5), size - 1.0);
    if (any(greaterThan(first_f, last_f))) {
        return;
    }
    uvec2 first = uvec2(first_f);
    uvec2 last = uvec2(last_f);
    uvec2 extent = last - first + 1u;
    if (extent.x * extent.y > params.counts.w) {
        if (hand_to_tiles(tet, first, last)) {
            return;
        }
        atomicAdd(stats[STAT_OVERFLOW], 1u);
    }
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            for (uint k = 0u; k < n; ++k) {
                shade_pixel(proxies[k], uvec2(x, y), tet);
            }
        }
    }
}
