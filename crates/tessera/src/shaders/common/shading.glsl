// Gooch shading; the constants come from the Rust side (tessera_data::shading) as #defines.

vec3 gooch(vec3 n, vec3 light, vec3 view) {
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    float t = (1.0 + dot(n, light)) * 0.5;
    vec3 cool = GOOCH_COOL;
    vec3 warm = GOOCH_WARM;
    vec3 base = cool + (warm - cool) * t;
    vec3 r = 2.0 * dot(n, light) * n - light;
    float spec = pow(max(dot(r, view), 0.0), SPECULAR_EXPONENT) * SPECULAR_STRENGTH;
    return base + vec3(spec);
}

// Colour of a rasterized surface point: world-space interpolated normal (any length; a zero
// normal falls back to facing the viewer) and position, seen from `eye`. Every rasterizing
// path shades through this, as tessera_data::rasterize::shade_fragment does on the CPU.
vec3 shade_surface(vec3 normal_world, vec3 position_world, vec3 eye, vec3 light) {
    vec3 view = normalize(eye - position_world);
    vec3 n = dot(normal_world, normal_world) > 0.0 ? normalize(normal_world) : view;
    return gooch(n, light, view);
}
