// What a pixel accumulates from one tet, given the interpolated proxy attributes (proxy.glsl). INTEGRAND (a define from Rust) selects it:
//   INTEGRAND_TET_ABSORPTION  length × the tet's absorption colour (paper A's optical depth)
//   INTEGRAND_ABSORPTION      length × the table's mean over the scalar's run (optical depth)
//   INTEGRAND_EMISSION        the same with an emission table (added light)
//   INTEGRAND_MAXIMUM         (largest scalar, 1, 0), combined by maximum
// The scalar is linear along the stretch, so the integral of the piecewise-linear table is its
// mean over [s_front, s_back] times the length: exact, whatever the stretch's length.
// Needs buffers.glsl, params.glsl, length.glsl and table.glsl.

vec3 integrand(vec4 attrs, vec2 ndc, vec3 tet_colour) {
#if INTEGRAND == INTEGRAND_MAXIMUM
    return vec3(clamp(max(attrs.z / attrs.x, attrs.w / second_inverse_depth(attrs)), 0.0, 1.0), 1.0, 0.0);
#else
    float len = interval_length(attrs, ndc);
#if INTEGRAND == INTEGRAND_TET_ABSORPTION
    return len * tet_colour;
#else
    return len * table_mean(attrs.z / attrs.x, attrs.w / second_inverse_depth(attrs));
#endif
#endif
}
