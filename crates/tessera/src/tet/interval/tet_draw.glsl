// The compute path's per-tet drawing, shared by its first pass (interval_raster.comp.glsl) and
// the binned path's counting pass (interval_bin_count.comp.glsl), which draws this way the tets
// its lists have no room for. A tet whose screen rectangle holds at most `params.counts.w`
// pixels is drawn by the calling invocation, each row across its span; a larger one is handed
// to the tile pass (interval_tiles.comp.glsl) as TILE × TILE-pixel tiles, one workgroup each,
// so that the few huge proxies near the eye do not leave one invocation walking a whole
// screen. Where the tile buffers are full, the tet is drawn by the invocation after all
// (slowly, but correctly). Needs splat.glsl and what it needs.

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

// The first and last pixel whose centres the proxies' screen rectangle holds; false when it
// holds none on screen.
bool proxy_pixel_rect(Proxy proxies[3], uint n, out uvec2 first, out uvec2 last) {
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    // Constant bounds, so that every index into the proxies is a constant (registers).
    for (uint k = 0u; k < 3u; ++k) {
        uint silhouette = k < n ? proxies[k].silhouette : 0u;
        for (uint j = 0u; j < 5u; ++j) {
            if (j <= silhouette && silhouette > 0u) {
                vec2 s = to_screen(proxies[k].p[j]);
                lo = min(lo, s);
                hi = max(hi, s);
            }
        }
    }
    vec2 size = vec2(params.counts.yz);
    vec2 first_f = max(ceil(lo - 0.5), vec2(0.0));
    vec2 last_f = min(floor(hi - 0.5), size - 1.0);
    first = uvec2(0u);
    last = uvec2(0u);
    if (any(greaterThan(first_f, last_f))) {
        return false;
    }
    first = uvec2(first_f);
    last = uvec2(last_f);
    return true;
}

// Widens [lo, hi] to the x that edge a-b takes while y runs over [y0, y1] (screen pixels).
void widen_to_edge(vec2 a, vec2 b, float y0, float y1, inout float lo, inout float hi) {
    if (max(a.y, b.y) < y0 || min(a.y, b.y) > y1) {
        return;
    }
    float dy = b.y - a.y;
    vec2 t = dy == 0.0 ? vec2(0.0, 1.0) : clamp((vec2(y0, y1) - a.y) / dy, 0.0, 1.0);
    vec2 x = a.x + t * (b.x - a.x);
    lo = min(lo, min(x.x, x.y));
    hi = max(hi, max(x.x, x.y));
}

// How far rounding may move the exact test's (splat.glsl) idea of the proxy's edges, in
// pixels: its edge functions subtract and multiply corner coordinates, each rounded to a unit
// in the last place of the largest (about 1.2e-7 of it), which by estimate moves an edge by
// at most about 1e-6 of that coordinate. Four times that, and no less than a hundredth of a
// pixel.
float rounding_slack(ProxyRaster proxy) {
    vec2 largest = abs(proxy.centre);
    for (uint j = 0u; j < 4u; ++j) {
        largest = max(largest, abs(proxy.corner[j]));
    }
    return max(0.01, 4e-6 * max(largest.x, largest.y));
}

// The pixels of row y whose centres the proxy's silhouette may hold, within the columns
// first.x..last.x: those whose centre lies within `slack` of the silhouette edges' crossings
// of a band 2 × slack high around the row's centre line. Every point within `slack` of the
// silhouette on the centre line is in it, so rounding never leaves out a pixel the exact test
// would give the tet. False when none.
bool proxy_row_span(ProxyRaster proxy, float slack, uint y, uvec2 first, uvec2 last, out uint x0, out uint x1) {
    float centre = float(y) + 0.5;
    float lo = 1e30;
    float hi = -1e30;
    for (uint j = 0u; j < 4u; ++j) {
        if (j < proxy.silhouette) {
            widen_to_edge(proxy.corner[j], proxy.corner[j + 1u], centre - slack, centre + slack, lo, hi);
        }
    }
    float from = max(ceil(lo - slack - 0.5), float(first.x));
    float to = min(floor(hi + slack - 0.5), float(last.x));
    // Clamped into the columns, so that an empty span (from = 1e30) converts to an integer too.
    x0 = uint(min(from, float(last.x)));
    x1 = uint(max(to, float(first.x)));
    return from <= to;
}

// Draws row y of one of tet `tet`'s proxies, across the proxy's span only (a triangular
// silhouette fills at most half of its rectangle first..last).
void draw_proxy_row(uint tet, ProxyRaster proxy, float slack, uint y, uvec2 first, uvec2 last) {
    uint x0;
    uint x1;
    if (proxy_row_span(proxy, slack, y, first, last, x0, x1)) {
        for (uint x = x0; x <= x1; ++x) {
            shade_pixel(proxy, uvec2(x, y), tet);
        }
    }
}

// Whether the tet with pixel rectangle first..last is to be drawn by the calling invocation:
// false where the tile pass takes it.
bool drawn_here(uint tet, uvec2 first, uvec2 last) {
    uvec2 extent = last - first + 1u;
    if (extent.x * extent.y > params.counts.w) {
        if (hand_to_tiles(tet, first, last)) {
            return false;
        }
        atomicAdd(stats[STAT_OVERFLOW], 1u);
    }
    return true;
}

// Draws tet `tet`'s `n` proxies (their pixel rectangle first..last) in the calling invocation,
// each row across its span.
void draw_proxies(uint tet, Proxy proxies[3], uint n, uvec2 first, uvec2 last) {
    for (uint k = 0u; k < 3u; ++k) {
        if (k < n) {
            ProxyRaster proxy = proxy_raster(proxies[k]);
            float slack = rounding_slack(proxy);
            for (uint y = first.y; y <= last.y; ++y) {
                draw_proxy_row(tet, proxy, slack, y, first, last);
            }
        }
    }
}

// Draws tet `tet` (its `n` proxies, their pixel rectangle first..last) here or through the
// tile pass.
void draw_tet(uint tet, Proxy proxies[3], uint n, uvec2 first, uvec2 last) {
    if (drawn_here(tet, first, last)) {
        draw_proxies(tet, proxies, n, first, last);
    }
}
