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
