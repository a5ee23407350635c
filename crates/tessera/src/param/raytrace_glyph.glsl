// Ray / SH glyph intersection after Peters et al. 2023, the f32 port of
// tessera_data::param::raytrace::intersect_glyph (its module documents the method and the
// changes from the paper): the glyph's squared implicit form F = R(x, h)^2 - (x^2 + h^2)^(k+1) as
// a polynomial of degree 2k + 2 along the ray, its first root by isolating the roots of every
// derivative in turn (Yuksel 2022), each by Newton steps safeguarded by bisection.
//
// Defines from Rust: RT_MAX_ORDER (largest SH order, sizes the arrays), RT_TABLE_STRIDE and
// RT_TABLE_SQUARE (layout of rt_vandermonde, tessera_data::param::raytrace::vandermonde_table),
// RT_BOUND_DIVISOR.

#ifndef PARAM_RAYTRACE_GLYPH_GLSL
#define PARAM_RAYTRACE_GLYPH_GLSL

#include "param/sh.glsl"

#define RT_MAX_DEGREE (2 * RT_MAX_ORDER + 2)
const float RT_PI = 3.14159265358979;
// Newton steps or bisections per root: every accepted Newton step is at most half the one
// before, and an f32 bracket of width 16 bisects down to rounding in ~26 steps.
const int RT_ROOT_ITERATIONS = 64;

layout(binding = 6, std430) readonly buffer RtVandermonde { float rt_vandermonde[]; };

// Per-invocation scratch: the polynomial, the current derivative and the roots of the previous.
float rt_poly[RT_MAX_DEGREE + 1];
float rt_deriv[RT_MAX_DEGREE + 1];
float rt_roots[RT_MAX_DEGREE + 1];
// R along the ray in the ray coordinate (coefficients by power), whose sign tells a positive lobe
// from a negative one; rt_lobe_degree < 0: every root of F is surface.
float rt_lobe[RT_MAX_ORDER + 1];
int rt_lobe_degree;

bool rt_on_lobe(float x) {
    if (rt_lobe_degree < 0) {
        return true;
    }
    float v = 0.0;
    for (int j = rt_lobe_degree; j >= 0; --j) {
        v = v * x + rt_lobe[j];
    }
    return v > 0.0;
}

// Value of rt_deriv (degree m) at x, and its derivative.
float rt_eval(int m, float x, out float slope) {
    float v = rt_deriv[m];
    slope = 0.0;
    for (int i = m - 1; i >= 0; --i) {
        slope = slope * x + v;
        v = v * x + rt_deriv[i];
    }
    return v;
}

float rt_value(int m, float x) {
    float slope;
    return rt_eval(m, x, slope);
}

// The root of rt_deriv (degree m, monotonic on [a, b], signs at a and b differ; zero counts as
// negative). Newton steps are kept while they stay in the bracket and at least halve the step
// before, else the bracket is bisected, so roots of high multiplicity are still bracketed.
float rt_bracketed_root(int m, float a, float b, bool a_positive, float tol) {
    float x = 0.5 * (a + b);
    float step = b - a;
    for (int i = 0; i < RT_ROOT_ITERATIONS; ++i) {
        float slope;
        float v = rt_eval(m, x, slope);
        if ((v > 0.0) == a_positive) {
            a = x;
        } else {
            b = x;
        }
        float newton = x - v / slope;
        float step_before = step;
        step = abs(newton - x);
        if (newton > a && newton < b && 2.0 * step <= step_before) {
            x = newton;
        } else {
            step = 0.5 * (b - a);
            x = 0.5 * (a + b);
        }
        if (step <= tol) {
            break;
        }
    }
    return x;
}

// The first root of rt_poly (degree n) in [lo, hi] where it changes sign and rt_on_lobe holds. Derivative m is
// F^(n-m) / (n-m)!, monotonic between the roots of derivative m - 1.
bool rt_first_root(int n, float lo, float hi, out float root) {
    float tol = 2e-7 * max(abs(lo), abs(hi));
    int count = 0;
    for (int m = 1; m <= n; ++m) {
        float binomial = 1.0;
        for (int j = 0; j <= m; ++j) {
            if (j > 0) {
                binomial *= float(j + n - m) / float(j);
            }
            rt_deriv[j] = binomial * rt_poly[j + n - m];
        }
        int found = 0;
        float a = lo;
        float fa = rt_value(m, lo);
        for (int i = 0; i <= count; ++i) {
            float b = i < count ? rt_roots[i] : hi;
            float fb = rt_value(m, b);
            if ((fa > 0.0) != (fb > 0.0) && b > a) {
                float r = rt_bracketed_root(m, a, b, fa > 0.0, tol);
                if (m == n) {
                    if (rt_on_lobe(r)) {
                        root = r;
                        return true;
                    }
                    a = b;
                    fa = fb;
                    continue;  // a negative lobe's surface, passed over
                }
                // found <= i: rt_roots[i] has been read already.
                rt_roots[found++] = r;
            }
            a = b;
            fa = fb;
        }
        count = found;
    }
    root = hi;  // where a ray that starts inside leaves through the clamp
    return false;
}

// Some unit vector perpendicular to d.
vec3 rt_perpendicular(vec3 d) {
    vec3 axis = abs(d.x) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    return normalize(cross(d, axis));
}

// The glyph's radius before clamping in direction e (any length): r * scale + offset.
float rt_radius(ParamObject o, vec3 e) {
    float theta = atan(length(e.xy), e.z);
    float phi = atan(e.y, e.x);
    float r = sh_evaluate(o.params, o.order, (o.flags >> PARAM_BASIS_SHIFT) & 3u, theta, phi);
    return r * o.radius_map.x + o.radius_map.y;
}

// First hit of the object-space ray o + t d (d of unit length) with the glyph of object
// `object` (bounding radius `bound`) for t in [t_min, t_max].
bool rt_intersect_glyph(uint object, float bound, vec3 o, vec3 d, float t_min, float t_max, out float t) {
    ParamObject obj = param_objects[object];
    int k = min(int(obj.order), RT_MAX_ORDER);  // Rust refuses higher; never index past arrays
    float q = dot(d, o);
    vec3 c = o - q * d;
    c -= dot(c, d) * d;
    float h = length(c);
    t = t_max;
    if (h >= bound) {
        return false;
    }
    // A ray through the centre lies in every plane that contains it.
    vec3 c_hat = h > 0.0 ? c / h : rt_perpendicular(d);
    float samples[RT_MAX_ORDER + 1];
    for (int i = 0; i <= k; ++i) {
        float alpha = float(i) * (RT_PI / float(k + 1));
        samples[i] = rt_radius(obj, cos(alpha) * d + sin(alpha) * c_hat);
    }
    // R(x, y) = sum a_j x^j y^(k-j) in the plane, and Peters' bound of the glyph within it.
    uint base = uint(k / 2) * RT_TABLE_STRIDE;
    float a[RT_MAX_ORDER + 1];
    float plane_bound = 0.0;
    for (int j = 0; j <= k; ++j) {
        float sum = 0.0;
        for (int i = 0; i <= k; ++i) {
            sum += rt_vandermonde[base + uint(j * (k + 1) + i)] * samples[i];
        }
        a[j] = sum;
        plane_bound += abs(sum) * rt_vandermonde[base + RT_TABLE_SQUARE + uint(j)];
    }
    bound = min(bound, plane_bound);
    if (h >= bound) {
        return false;
    }
    // In u = x / L, L = max(h, bound / 8), F stays within f32 (module notes on the CPU side).
    float scale = max(h, bound / RT_BOUND_DIVISOR);
    float eta = h / scale;
    int n = 2 * k + 2;
    for (int i = 0; i <= n; ++i) {
        rt_poly[i] = 0.0;
    }
    float power = 1.0;  // eta^(k - j)
    for (int j = k; j >= 0; --j) {
        a[j] *= power / scale;
        power *= eta;
        rt_lobe[j] = a[j];
    }
    rt_lobe_degree = (obj.flags & PARAM_FLAG_POSITIVE_LOBES) != 0u ? k : -1;
    for (int i = 0; i <= k; ++i) {
        for (int j = 0; j <= k; ++j) {
            rt_poly[i + j] += a[i] * a[j];
        }
    }
    // - (u^2 + eta^2)^(k+1): C(k+1, i) eta^(2(k+1-i)) u^(2i), from i = k + 1 down.
    float binomial = 1.0;
    power = 1.0;
    for (int i = k + 1; i >= 0; --i) {
        rt_poly[2 * i] -= binomial * power;
        binomial *= float(i) / float(k + 2 - i);
        power *= eta * eta;
    }
    float half_chord = sqrt(max(bound * bound - h * h, 0.0));
    float lo = max(q + t_min, -half_chord) / scale;
    float hi = min(q + t_max, half_chord) / scale;
    if (lo > hi) {
        return false;
    }
    rt_deriv = rt_poly;
    bool starts_inside = rt_value(n, lo) > 0.0 && rt_on_lobe(lo);
    float u;
    if (starts_inside && q + t_min <= -half_chord) {
        u = lo;  // entering the bounding sphere inside the glyph: the upper clamp is the surface
    } else if (!rt_first_root(n, lo, hi, u) && !(starts_inside && q + t_max >= half_chord)) {
        return false;  // (starting inside, the way out may be through the clamp, at hi)
    }
    t = u * scale - q;
    return true;
}

#endif
