#version 460
// Binned compute path of interval shading, last pass: one workgroup per screen tile, one
// invocation per pixel, walks the tile's list of tets. A list of up to BIN_SORT_CAPACITY tets
// is first sorted in shared memory: by tet id, so that the sums do not depend on the order the
// scatter's atomics left (longer lists keep it); for INTEGRAND_SDF, whose nearest hit does not
// depend on the order, front to back, so that a pixel skips more of the tets behind its
// nearest hit. BIN_BATCH invocations make a batch of tets'
// proxies and pixel rectangles into shared memory; every invocation then evaluates them at its
// pixel centre exactly as the per-tet passes do (splat.glsl) and combines the values in a
// register. Each pixel is written once, onto what the per-tet path drew of the tets the lists
// had no room for.
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif
#extension GL_EXT_shader_atomic_float : require

layout(local_size_x = TILE, local_size_y = TILE) in;

#include "tet/interval/pixel_passes.glsl"
#include "tet/interval/bin_buffers.glsl"
#include "tet/interval/tet_draw.glsl"

shared uint tile_tets[BIN_SORT_CAPACITY];
shared Proxy batch_proxies[BIN_BATCH * 3];
shared uint batch_proxy_count[BIN_BATCH];
shared uint batch_tet[BIN_BATCH];
// The pixels the tet's proxies may cover (first.xy, last.xy), as the per-tet passes bound them.
shared uvec4 batch_rect[BIN_BATCH];

const uint INVOCATIONS = uint(TILE * TILE);

#if INTEGRAND == INTEGRAND_SDF
// The sort key of the tile's `i`-th listed tet: its nearest corner's view depth (clip w, 0 for a
// corner behind the eye) with its low bits replaced by `i`, which finds the tet again
// (listed_tet). Positive floats order as their bits do; equal depths in what is kept (12 bits of
// mantissa) keep the list's order.
uint sort_key(uint tet, uint i) {
    uvec4 corners = tets[tet];
    float nearest = 1e30;
    for (uint j = 0u; j < 4u; ++j) {
        nearest = min(nearest, (params.world_to_clip * vec4(vertices_world[corners[j]].xyz, 1.0)).w);
    }
    return (floatBitsToUint(max(nearest, 0.0)) & ~(uint(BIN_SORT_CAPACITY) - 1u)) | i;
}

uint listed_tet(uint start, uint key) {
    return bin_list[start + (key & (uint(BIN_SORT_CAPACITY) - 1u))];
}
#else
uint sort_key(uint tet, uint i) {
    return tet;
}

uint listed_tet(uint start, uint key) {
    return key;
}
#endif

// Sorts the first `count` (at most BIN_SORT_CAPACITY) keys of `tile_tets` in place: a bitonic
// sort over the next power of two, padded with the largest key (NO_TET).
void sort_tile_tets(uint count) {
    uint padded = count <= 1u ? 1u : 1u << (findMSB(count - 1u) + 1);
    for (uint i = gl_LocalInvocationIndex + count; i < padded; i += INVOCATIONS) {
        tile_tets[i] = NO_TET;
    }
    barrier();
    for (uint k = 2u; k <= padded; k <<= 1) {
        for (uint j = k >> 1; j > 0u; j >>= 1) {
            for (uint i = gl_LocalInvocationIndex; i < padded; i += INVOCATIONS) {
                uint l = i ^ j;
                if (l > i) {
                    uint a = tile_tets[i];
                    uint b = tile_tets[l];
                    if ((a > b) == ((i & k) == 0u)) {
                        tile_tets[i] = b;
                        tile_tets[l] = a;
                    }
                }
            }
            barrier();
        }
    }
}

// Combines `value` with what the per-tet path left at `pixel` (added, or the larger or nearer
// kept): nothing else writes the pixel in this pass, so no atomics.
void store_pixel(uint pixel, PixelValue value) {
#if INTEGRAND == INTEGRAND_SDF
    frame[pixel * 2u] = combine_pixel_values(frame[pixel * 2u], value);
#else
#if INTEGRAND == INTEGRAND_MAXIMUM
    // Non-negative floats order as their bits do.
    optical[optical_index(pixel, 0u)] = max(optical[optical_index(pixel, 0u)], floatBitsToUint(value.x));
    optical[optical_index(pixel, 1u)] = max(optical[optical_index(pixel, 1u)], floatBitsToUint(value.y));
#else
    optical[optical_index(pixel, 0u)] += value.x;
    optical[optical_index(pixel, 1u)] += value.y;
    optical[optical_index(pixel, 2u)] += value.z;
#endif
#endif
}

void main() {
    // Uniform per workgroup, so returning before the barriers is allowed.
    if (!bins_hold_screen()) {
        return;
    }
    uint tile = gl_WorkGroupID.y * bin_grid().x + gl_WorkGroupID.x;
    uint start = tile == 0u ? 0u : tile_bins[tile - 1u];
    uint end = tile_bins[tile];
    uvec2 pixel = gl_WorkGroupID.xy * uint(TILE) + gl_LocalInvocationID.xy;
    bool on_screen = all(lessThan(pixel, params.counts.yz));
    vec2 ndc = pixel_ndc(pixel);
    PixelValue value = empty_pixel_value();
    uint local = gl_LocalInvocationIndex;
    // Uniform per workgroup, as are the loop bounds below: the barriers are reached by all.
    bool sorted = end - start <= uint(BIN_SORT_CAPACITY);
    if (sorted) {
        for (uint i = local; i < end - start; i += INVOCATIONS) {
            tile_tets[i] = sort_key(bin_list[start + i], i);
        }
        sort_tile_tets(end - start);
    }
    for (uint batch = start; batch < end; batch += uint(BIN_BATCH)) {
        uint count = min(end - batch, uint(BIN_BATCH));
        if (local < count) {
            uint tet = sorted ? listed_tet(start, tile_tets[batch - start + local]) : bin_list[batch + local];
            Proxy proxies[3];
            bool clipped;
            uint n = tet_proxies(tet, proxies, clipped);
            uvec2 first;
            uvec2 last;
            // Listed tets have a rectangle on screen (the counting pass found it alike).
            proxy_pixel_rect(proxies, n, first, last);
            batch_proxy_count[local] = n;
            for (uint k = 0u; k < 3u; ++k) {
                batch_proxies[local * 3u + k] = proxies[k];
            }
            batch_tet[local] = tet;
            batch_rect[local] = uvec4(first, last);
        }
        barrier();
        for (uint i = 0u; i < count && on_screen; ++i) {
            uvec4 rect = batch_rect[i];
            if (any(lessThan(pixel, rect.xy)) || any(greaterThan(pixel, rect.zw))) {
                continue;
            }
            for (uint k = 0u; k < batch_proxy_count[i]; ++k) {
                vec4 attrs;
                if (proxy_attrs_at(batch_proxies[i * 3u + k], pixel, attrs)) {
                    value = combine_pixel_values(value, tet_pixel_value(batch_tet[i], attrs, ndc, value));
                }
            }
        }
        barrier();
    }
    if (on_screen && end > start) {
        store_pixel(pixel.y * params.counts.y + pixel.x, value);
    }
}
