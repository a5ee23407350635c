#version 460
// Binned compute path of interval shading, first pass: one invocation per tet makes its
// proxies (tet/interval/proxy.glsl), reserves one entry per screen tile of its pixel rectangle
// that its proxies may touch (every tile of the rectangle where that holds more than
// BIN_TESTED_TILES tiles, or where a proxy corner lies far off screen) and counts itself into
// each such tile. A tet whose entries do not fit is drawn at once by the per-tet path
// (tet/interval/tet_draw.glsl, global atomics), so no tet is ever lost; the host grows the
// entries for the next frame from the reserved total.
#extension GL_EXT_shader_atomic_float : require
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif

layout(local_size_x = TETS_PER_WORKGROUP) in;

#include "tet/interval/pixel_passes.glsl"
#include "tet/interval/bin_buffers.glsl"
#include "tet/interval/tet_draw.glsl"

// Whether `proxy` may cover a pixel centre inside lo..hi: false only where one edge of its
// silhouette (a convex polygon around the inner vertex) has the whole box strictly on its outer
// side. Edges through the inner vertex decide nothing (conservative).
bool proxy_may_touch(Proxy proxy, vec2 lo, vec2 hi) {
    uint s = proxy.silhouette;
    if (s == 0u) {
        return false;
    }
    vec2 centre = to_screen(proxy.p[s]);
    for (uint j = 0u; j < s; ++j) {
        vec2 a = to_screen(proxy.p[j]);
        vec2 b = to_screen(proxy.p[j + 1u == s ? 0u : j + 1u]);
        float inner = edge(a, b, centre);
        vec4 corners = vec4(edge(a, b, lo), edge(a, b, vec2(hi.x, lo.y)),
                            edge(a, b, vec2(lo.x, hi.y)), edge(a, b, hi));
        if ((inner > 0.0 && all(lessThan(corners, vec4(0.0)))) ||
            (inner < 0.0 && all(greaterThan(corners, vec4(0.0))))) {
            return false;
        }
    }
    return true;
}

// Whether any of the `n` proxies may cover a pixel centre of `tile`. The box of its centres is
// grown by a pixel, so that rounding never drops a tile a proxy covers.
bool tile_touched(Proxy proxies[3], uint n, uvec2 tile) {
    vec2 lo = vec2(tile * uint(TILE)) - 0.5;
    vec2 hi = vec2(tile * uint(TILE)) + float(TILE) + 0.5;
    for (uint k = 0u; k < n; ++k) {
        if (proxy_may_touch(proxies[k], lo, hi)) {
            return true;
        }
    }
    return false;
}

// Whether every proxy corner lies within a screen's size of the screen: there the tile test's
// rounding stays far below its margin (a clipped tet's corners may lie very far out).
bool proxies_near_screen(Proxy proxies[3], uint n) {
    vec2 size = vec2(params.counts.yz);
    for (uint k = 0u; k < n; ++k) {
        for (uint j = 0u; j <= proxies[k].silhouette && proxies[k].silhouette > 0u; ++j) {
            vec2 s = to_screen(proxies[k].p[j]);
            if (any(lessThan(s, -size)) || any(greaterThan(s, 2.0 * size))) {
                return false;
            }
        }
    }
    return true;
}

// Whether the entry for `tile` is made: one of the proxies may touch it, or the tiles are not
// tested.
bool listed(bool tested, Proxy proxies[3], uint n, uvec2 tile) {
    return !tested || tile_touched(proxies, n, tile);
}

// The workgroup reserves its tets' entries with one atomic add (a per-tet add on one counter
// would serialize millions of tets).
shared uint group_entries;
shared uint group_base;

void main() {
    // Workgroups spread over x and y past 65,535 (tessera_gpu::spread_groups).
    uint tet = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * uint(TETS_PER_WORKGROUP) + gl_LocalInvocationIndex;
    Proxy proxies[3];
    uint n = first_tet_proxies(tet, proxies);
    uvec2 first = uvec2(0u);
    uvec2 last = uvec2(0u);
    bool on_screen = n > 0u && proxy_pixel_rect(proxies, n, first, last);
    uvec2 first_tile = first / uint(TILE);
    uvec2 tiles = on_screen ? last / uint(TILE) - first_tile + 1u : uvec2(0u);
    // A large rectangle is listed whole: one invocation walks it, so the walk must be cheap.
    bool tested = tiles.x * tiles.y <= uint(BIN_TESTED_TILES) && proxies_near_screen(proxies, n);
    uint count = tested ? 0u : tiles.x * tiles.y;
    for (uint y = 0u; y < tiles.y && tested; ++y) {
        for (uint x = 0u; x < tiles.x; ++x) {
            count += tile_touched(proxies, n, first_tile + uvec2(x, y)) ? 1u : 0u;
        }
    }
    // Barriers in uniform control flow: every invocation reaches them.
    if (gl_LocalInvocationIndex == 0u) {
        group_entries = 0u;
    }
    barrier();
    uint offset = atomicAdd(group_entries, count);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        group_base = atomicAdd(bin_entry_count, group_entries);
    }
    barrier();
    if (!on_screen) {
        return;
    }
    uint base = group_base + offset;
    uint capacity = uint(bin_entries.length());
    bool fits = bins_hold_screen() && base + count <= capacity && base + count >= base;
    if (!fits) {
        // The scatter pass skips the part of the reservation that lies inside the buffer.
        for (uint e = base; e < min(base + count, capacity); ++e) {
            bin_entries[e] = uvec2(NO_TET, 0u);
        }
        atomicAdd(stats[STAT_UNBINNED], 1u);
        draw_tet(tet, proxies, n, first, last);
        return;
    }
    uint columns = bin_grid().x;
    uint e = base;
    for (uint y = 0u; y < tiles.y; ++y) {
        for (uint x = 0u; x < tiles.x; ++x) {
            if (listed(tested, proxies, n, first_tile + uvec2(x, y))) {
                uint tile = (first_tile.y + y) * columns + first_tile.x + x;
                atomicAdd(tile_bins[tile], 1u);
                bin_entries[e++] = uvec2(tet, tile);
            }
        }
    }
}
