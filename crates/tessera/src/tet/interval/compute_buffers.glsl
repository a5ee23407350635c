// The compute path's buffers after buffers.glsl (host side: `IntervalCompute::record`).
#if INTEGRAND == INTEGRAND_SDF
// Two 64-bit words per pixel; the first holds depth << 32 | packed colour, all ones when empty.
layout(binding = 5) buffer Frame { uint64_t frame[]; };
#else
// Laid out by optical_layout.glsl.
#include "tet/interval/optical_layout.glsl"
#if INTEGRAND == INTEGRAND_MAXIMUM
layout(binding = 5) buffer Optical { uint optical[]; };
#else
layout(binding = 5) buffer Optical { float optical[]; };
#endif

uint optical_index(uint pixel, uint channel) {
    return optical_index(pixel, channel, params.counts.y * params.counts.z);
}
#endif
// Tets too large to draw in one invocation: tet, first tile, first pixel (x | y << 16), tiles
// per row of their screen rectangle.
layout(binding = 6) buffer TiledTets { uvec4 tiled_tets[]; };
// Per tile, the tiled tet it belongs to (NO_TET where its allocation overflowed).
layout(binding = 7) buffer TileOwners { uint tile_owner[]; };
layout(binding = 8) buffer TileCount {
    uint tile_count;
    uint tile_dispatch[3];
};

const uint NO_TET = 0xffffffffu;
