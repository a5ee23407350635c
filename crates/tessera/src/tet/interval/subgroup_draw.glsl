// The per-tet pass's drawing shared by a subgroup: the subgroup's unclipped tets that one
// invocation would draw (tet_draw.glsl's drawn_here) and whose rectangle holds more than
// SUBGROUP_DRAW_ABOVE_PIXELS pixels are drawn one after another by all its invocations,
// neighbouring invocations taking neighbouring pixels of the tet's row spans. Their atomics
// then meet a few memory sectors rather than one each (an invocation walking its
// own tet's rows sends each atomic of a subgroup to a different place), and a large tet's
// pixels are spread over the subgroup rather than left to one invocation. On the H200 the
// 2.4 M-tet box's far frame went from 9.14 to 8.27 ms and its close frame from 29.97 to 21.60
// (run 93; its scalar field's far frame lost, 9.52 to 10.61); the subgroup's pixels taken
// across the tet's whole rectangle rather than its spans gained less (9.36 / 27.35), and the
// same drawing shared by a workgroup through shared memory lost (21-33 ms far; runs 91, 92).
// Needs subgroup ballot, shuffle and arithmetic enabled, tet_draw.glsl and what it needs.

#include "common/subgroup_turns.glsl"

// The number of pixels above which this subgroup draws a tet together: SUBGROUP_DRAW_ABOVE_PIXELS,
// or with SUBGROUP_DRAW_CHOSEN the one of SUBGROUP_DRAW_LIMITS whose estimated time is least
// for the subgroup's tets. An invocation's `pixels` is its tet's rectangle (0 where it draws
// none; `groupable` false where the tet must be drawn alone). The estimate: the largest
// rectangle one invocation draws alone, plus, for each tet drawn together, its rectangle
// spread over the subgroup and SUBGROUP_DRAW_SETUP_PIXELS for the tet's set-up. Call from
// uniform control flow.
uint subgroup_draw_limit(bool groupable, uint pixels) {
#if SUBGROUP_DRAW_CHOSEN
    const uint limits[] = SUBGROUP_DRAW_LIMITS;
    uint chosen = limits[0];
    uint least = 0xffffffffu;
    for (uint k = 0u; k < uint(limits.length()); ++k) {
        bool together = groupable && pixels > limits[k];
        uint alone = subgroupMax(together ? 0u : pixels);
        uint spread = subgroupAdd(together ? SUBGROUP_DRAW_SETUP_PIXELS + pixels / gl_SubgroupSize : 0u);
        if (alone + spread < least) {
            least = alone + spread;
            chosen = limits[k];
        }
    }
    return chosen;
#else
    return SUBGROUP_DRAW_ABOVE_PIXELS;
#endif
}

// Invocation `lane`'s proxy, for every invocation.
Proxy shuffle_proxy(Proxy proxy, uint lane) {
    Proxy p;
    for (uint j = 0u; j < 5u; ++j) {
        p.p[j] = subgroupShuffle(proxy.p[j], lane);
        p.attrs[j] = subgroupShuffle(proxy.attrs[j], lane);
    }
    p.silhouette = subgroupShuffle(proxy.silhouette, lane);
    return p;
}

// Draws, with the whole subgroup, the tets for which `grouped` holds (one proxy, pixel
// rectangle first..last). Call from uniform control flow.
void draw_subgroup(bool grouped, uint tet, Proxy proxy, uvec2 first, uvec2 last) {
    uint me = gl_SubgroupInvocationID;
    uint lanes = gl_SubgroupSize;
    uvec4 pending = subgroupBallot(grouped);
    while (subgroup_turns_left(pending)) {
        uint lane = subgroup_next_turn(pending);
        ProxyRaster raster = proxy_raster(shuffle_proxy(proxy, lane));
        uint drawn = subgroupShuffle(tet, lane);
        uvec2 from = subgroupShuffle(first, lane);
        uvec2 to = subgroupShuffle(last, lane);
        float slack = rounding_slack(raster);
        // A row per invocation: its span, laid end to end with the other rows' spans; each
        // invocation then takes every `lanes`-th pixel of the run.
        for (uint rows = from.y; rows <= to.y; rows += lanes) {
            uint y = rows + me;
            uint x0 = 0u;
            uint x1 = 0u;
            bool spanned = y <= to.y && proxy_row_span(raster, slack, y, from, to, x0, x1);
            uint width = spanned ? x1 - x0 + 1u : 0u;
            uint start = subgroupExclusiveAdd(width);
            uint total = subgroupAdd(width);
            for (uint run = 0u; run < total; run += lanes) {
                uint i = run + me;
                // The last row whose span starts at or before i holds it (rows before it that
                // start there too are empty). gl_SubgroupSize is a power of two.
                uint row = 0u;
                for (uint step = lanes / 2u; step > 0u; step /= 2u) {
                    row += subgroupShuffle(start, row + step) <= i ? step : 0u;
                }
                uint x = subgroupShuffle(x0, row) + i - subgroupShuffle(start, row);
                if (i < total) {
                    shade_pixel(raster, uvec2(x, rows + row), drawn);
                }
            }
        }
    }
}
