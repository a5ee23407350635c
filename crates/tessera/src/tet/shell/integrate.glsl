// Front-to-back emission–absorption as tessera_data::tet::emission_absorption::FrontToBack
// adds a tet stretch: optical depth and emitted light from the tables' means over the
// stretch's linear scalar run, emission attenuated as in a homogeneous stretch.
// Needs buffers.glsl and tet/table.glsl.

struct FrontToBack {
    vec3 colour;
    vec3 transmittance;
};

// (1 - e^(-τ)) / τ. Below 1e-3 the f32 difference would lose most of its digits; there the
// series' next term is under 1e-10.
vec3 attenuation(vec3 tau) {
    vec3 series = 1.0 - tau * (0.5 - tau / 6.0);
    vec3 closed = (1.0 - exp(-tau)) / max(tau, vec3(1e-3));
    return mix(series, closed, greaterThan(tau, vec3(1e-3)));
}

// add_stretch with the stretch's emission scaled by `light` per channel (the effects);
// absorption is untouched.
void add_lit_stretch(inout FrontToBack sum, float s_in, float s_out, float len, vec3 light) {
    if (!(len > 0.0) || isnan(s_in) || isnan(s_out) || isinf(s_in) || isinf(s_out)) {
        return;
    }
    vec3 tau = table_mean_at(ABSORPTION_TABLE, s_in, s_out) * len;
    vec3 emitted = table_mean_at(EMISSION_TABLE, s_in, s_out) * len * light;
    sum.colour += sum.transmittance * emitted * attenuation(tau);
    sum.transmittance *= exp(-tau);
}

void add_stretch(inout FrontToBack sum, float s_in, float s_out, float len) {
    add_lit_stretch(sum, s_in, s_out, len, vec3(1.0));
}

// Opacity of the most transparent channel reached the early-termination threshold.
bool is_opaque(FrontToBack sum) {
    float most = max(max(sum.transmittance.r, sum.transmittance.g), sum.transmittance.b);
    return 1.0 - most >= EARLY_TERMINATION_OPACITY;
}
