// What one tet adds to a pixel on the compute path, and how two such values combine: the
// integrand (summed, or for INTEGRAND_MAXIMUM the larger kept), or for INTEGRAND_SDF the
// asteroid's hit packed as depth << 32 | colour (the nearer kept). The per-tet passes combine
// with global atomics (splat.glsl), the binned pass in registers. Needs buffers.glsl,
// params.glsl, length.glsl, integrand.glsl (and sdf.glsl for INTEGRAND_SDF).

#if INTEGRAND == INTEGRAND_SDF
#define PixelValue uint64_t
// No hit: all ones, the value empty pixels start at.
const uint64_t NO_HIT = 0xffffffffffffffffUL;

PixelValue empty_pixel_value() {
    return NO_HIT;
}

// What tet `tet` adds where `so_far` is what the pixel holds already (only the binned pass
// knows it; the per-tet passes give empty_pixel_value()): a tet whose interval begins behind
// the nearest hit so far is not traced.
PixelValue tet_pixel_value(uint tet, vec4 attrs, vec2 ndc, PixelValue so_far) {
    float nearest = so_far == NO_HIT ? 1e30 : uintBitsToFloat(uint(so_far >> 32));
    vec4 hit = asteroid_hit(tet, attrs, ndc, nearest);
    if (hit.w < 0.0) {
        return NO_HIT;
    }
    // Depth in the high word: non-negative floats order as their bits do.
    return (uint64_t(floatBitsToUint(hit.w)) << 32) | uint64_t(packUnorm4x8(vec4(hit.rgb, 1.0)));
}

PixelValue combine_pixel_values(PixelValue a, PixelValue b) {
    return a < b ? a : b;
}
#else
#define PixelValue vec3

PixelValue empty_pixel_value() {
    return vec3(0.0);
}

// What tet `tet` adds; `so_far` (what the pixel holds already) does not matter to a sum or a
// maximum.
PixelValue tet_pixel_value(uint tet, vec4 attrs, vec2 ndc, PixelValue so_far) {
    return integrand(attrs, ndc, absorption[tet].rgb);
}

PixelValue combine_pixel_values(PixelValue a, PixelValue b) {
#if INTEGRAND == INTEGRAND_MAXIMUM
    return max(a, b);
#else
    return a + b;
#endif
}
#endif
