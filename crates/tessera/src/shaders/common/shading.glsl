// Gooch shading; the constants come from the Rust side (tessera_data::shading) as #defines.

// n turned towards the viewer: surfaces and volume gradients are shaded two-sided.
vec3 facing(vec3 n, vec3 view) {
    return dot(n, view) < 0.0 ? -n : n;
}

// The Phong highlight of every shaded thing (surfaces and gradient-shaded volumes): unit
// normal facing the viewer, unit light and view directions.
float specular(vec3 n, vec3 light, vec3 view) {
    vec3 r = 2.0 * dot(n, light) * n - light;
    return pow(max(dot(r, view), 0.0), SPECULAR_EXPONENT) * SPECULAR_STRENGTH;
}

vec3 gooch(vec3 n, vec3 light, vec3 view) {
    n = facing(n, view);
    float t = (1.0 + dot(n, light)) * 0.5;
    vec3 cool = GOOCH_COOL;
    vec3 warm = GOOCH_WARM;
    vec3 base = cool + (warm - cool) * t;
    return base + vec3(specular(n, light, view));
}

// Colour of a rasterized surface point: world-space interpolated normal (any length; a zero
// normal falls back to facing the viewer) and position, seen from `eye`. Every rasterizing
// path shades through this, as tessera_data::rasterize::shade_fragment does on the CPU.
vec3 shade_surface(vec3 normal_world, vec3 position_world, vec3 eye, vec3 light) {
    vec3 view = normalize(eye - position_world);
    vec3 n = dot(normal_world, normal_world) > 0.0 ? normalize(normal_world) : view;
    return gooch(n, light, view);
}
