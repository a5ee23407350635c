// Real spherical harmonics of the even (antipodally symmetric) basis, mirroring
// tessera_data::param::sh: K_l^m by the fully normalised three-term recurrence per column m,
// combined with cos(m phi) / sin(m phi) as DIPY's descoteaux07 and tournier07 bases do (legacy
// or not). Coefficients are DIPY-ordered (l = 0, 2, ..., L; m = -l..l) in param_values.
//
// sh_recurrence holds, at a * SH_TABLE_WIDTH + l (built in f64 on the CPU, param/scene.rs):
// l == a: (K_a^a / sin^a theta, 0); l == a + 1: (sqrt(2a + 3), 0); l >= a + 2: (a_lm, b_lm) with
// K_l^a = a_lm (cos theta K_{l-1}^a - b_lm K_{l-2}^a). cos(m phi) and sin(m phi) come from the
// angle-addition recurrence rather than cos(m * phi), whose argument would lose ~m ulps.

#ifndef PARAM_SH_GLSL
#define PARAM_SH_GLSL

#include "param/scene.glsl"

// The weights of K_l^a in the m = +a and m = -a functions (a > 0) at the azimuth phi with
// cos(a phi) = cm and sin(a phi) = sm (module table in sh.rs).
vec2 sh_weights(uint a, uint basis, float cm, float sm) {
    bool tournier = basis >= SH_TOURNIER_LEGACY;
    bool legacy = basis == SH_DESCOTEAUX_LEGACY || basis == SH_TOURNIER_LEGACY;
    float scale = (tournier && legacy) ? 1.0 : sqrt(2.0);
    float w_pos = tournier ? scale * cm : scale * sm;
    float w_neg = tournier ? scale * sm : scale * cm;
    if (!tournier && !legacy && (a & 1u) == 1u) {
        w_neg = -w_neg;
    }
    return vec2(w_pos, w_neg);
}

// (cos, sin) of (a + 1) phi from those of a phi and of phi (`step`), by angle addition.
vec2 sh_next_azimuth(vec2 cs, vec2 step) {
    return vec2(cs.x * step.x - cs.y * step.y, cs.y * step.x + cs.x * step.y);
}

// K_l^a from K_{l-1}^a (cur) and K_{l-2}^a (prev), x = cos theta; l > a.
void sh_next(uint a, uint l, float x, inout float prev, inout float cur) {
    uint row = a * SH_TABLE_WIDTH;
    if (l == a + 1u) {
        prev = cur;
        cur = sh_recurrence[row + l].x * x * cur;
    } else {
        vec2 ab = sh_recurrence[row + l];
        float next = ab.x * (x * cur - ab.y * prev);
        prev = cur;
        cur = next;
    }
}

// sum_j c_j Y_j(theta, phi) for the order-`order` coefficients starting at param_values[first].
float sh_evaluate(uint first, uint order, uint basis, float theta, float phi) {
    float s = sin(theta);
    float x = cos(theta);
    vec2 step = vec2(cos(phi), sin(phi));
    vec2 cs = vec2(1.0, 0.0);  // cos(a phi), sin(a phi)
    float spow = 1.0;          // sin^a theta
    float sum = 0.0;
    for (uint a = 0u; a <= order; ++a) {
        if (a > 0u) {
            cs = sh_next_azimuth(cs, step);
            spow *= s;
        }
        vec2 w = sh_weights(a, basis, cs.x, cs.y);
        float prev = 0.0;
        float cur = sh_recurrence[a * SH_TABLE_WIDTH + a].x * spow;
        for (uint l = a; l <= order; ++l) {
            if (l > a) {
                sh_next(a, l, x, prev, cur);
            }
            if ((l & 1u) == 0u) {
                uint centre = first + l * (l + 1u) / 2u;  // index of (l, m = 0)
                if (a == 0u) {
                    sum += param_values[centre] * cur;
                } else {
                    sum += param_values[centre + a] * (w.x * cur) + param_values[centre - a] * (w.y * cur);
                }
            }
        }
    }
    return sum;
}

// sh_evaluate and its partial derivatives: (sum, d sum / d theta, d sum / d phi), the
// recurrence carried forward with the derivative of each K_l^a alongside (forward-mode
// differentiation; d cos(theta) = -sin(theta), d sin^a(theta) = a sin^(a-1)(theta) cos(theta)).
// The sum is formed in sh_evaluate's order.
vec3 sh_evaluate_gradient(uint first, uint order, uint basis, float theta, float phi) {
    float s = sin(theta);
    float x = cos(theta);
    vec2 step = vec2(cos(phi), sin(phi));
    vec2 cs = vec2(1.0, 0.0);  // cos(a phi), sin(a phi)
    float spow = 1.0;          // sin^a theta
    float spow_below = 0.0;    // sin^(a-1) theta
    vec3 sum = vec3(0.0);
    for (uint a = 0u; a <= order; ++a) {
        if (a > 0u) {
            cs = sh_next_azimuth(cs, step);
            spow_below = spow;
            spow *= s;
        }
        vec2 w = sh_weights(a, basis, cs.x, cs.y);
        // sh_weights is linear in (cos, sin): its derivative along phi takes a (-sin, cos).
        vec2 w_phi = sh_weights(a, basis, -float(a) * cs.y, float(a) * cs.x);
        uint row = a * SH_TABLE_WIDTH;
        float prev = 0.0;
        float prev_theta = 0.0;
        float cur = sh_recurrence[row + a].x * spow;
        float cur_theta = sh_recurrence[row + a].x * float(a) * spow_below * x;
        for (uint l = a; l <= order; ++l) {
            if (l == a + 1u) {
                float k = sh_recurrence[row + l].x;
                float next_theta = k * (x * cur_theta - s * cur);
                prev = cur;
                prev_theta = cur_theta;
                cur = k * x * cur;
                cur_theta = next_theta;
            } else if (l > a) {
                vec2 ab = sh_recurrence[row + l];
                float next = ab.x * (x * cur - ab.y * prev);
                float next_theta = ab.x * (x * cur_theta - s * cur - ab.y * prev_theta);
                prev = cur;
                prev_theta = cur_theta;
                cur = next;
                cur_theta = next_theta;
            }
            if ((l & 1u) == 0u) {
                uint centre = first + l * (l + 1u) / 2u;  // index of (l, m = 0)
                if (a == 0u) {
                    float c0 = param_values[centre];
                    sum += vec3(c0 * cur, c0 * cur_theta, 0.0);
                } else {
                    float cp = param_values[centre + a];
                    float cn = param_values[centre - a];
                    sum += vec3(cp * (w.x * cur) + cn * (w.y * cur),
                                cp * (w.x * cur_theta) + cn * (w.y * cur_theta),
                                cp * (w_phi.x * cur) + cn * (w_phi.y * cur));
                }
            }
        }
    }
    return sum;
}

// For one a, the polar half of sh_evaluate: sums over the even l of the m = +a and m = -a
// coefficients times K_l^a(theta) (for a = 0 both the m = 0 sum), so that at any azimuth
// the SH sum is the a = 0 sum plus, per a, sh_weights . these sums. Rounds differently from
// sh_evaluate (the products are summed per a first); for passes held to a tolerance.
vec2 sh_polar_sums(uint first, uint order, uint a, float theta) {
    float s = sin(theta);
    float spow = 1.0;
    for (uint i = 0u; i < a; ++i) {
        spow *= s;
    }
    float x = cos(theta);
    float prev = 0.0;
    float cur = sh_recurrence[a * SH_TABLE_WIDTH + a].x * spow;
    vec2 sums = vec2(0.0);
    for (uint l = a; l <= order; ++l) {
        if (l > a) {
            sh_next(a, l, x, prev, cur);
        }
        if ((l & 1u) == 0u) {
            uint centre = first + l * (l + 1u) / 2u;
            sums += vec2(param_values[centre + a], param_values[centre - a]) * cur;
        }
    }
    return sums;
}

#endif
