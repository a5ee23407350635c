// Unit normal of an object's world-space surface by finite differences, a port of
// tessera_data::param::functions::surface_normal (steps of 1/1024 of each range, one-sided at the
// domain's edges, a collapsed partial re-measured 1/256 of the other range inside the domain).
// Returns vec3(0) where the CPU returns None.

#ifndef PARAM_NORMAL_GLSL
#define PARAM_NORMAL_GLSL

#include "param/functions.glsl"

// The world point at parameter s along u (held = v) or along v (held = u).
vec3 param_line_point(uint object, bool along_u, float s, float held) {
    return along_u ? param_world_position(object, s, held) : param_world_position(object, held, s);
}

bool param_finite(vec3 d) {
    return !any(isnan(d)) && !any(isinf(d));
}

// Second-order difference along one parameter at x; false where the CPU gives None.
bool param_derivative(uint object, bool along_u, float held, float x, float lo, float hi, float h,
                      out vec3 d) {
    bool inside = x >= lo && x <= hi;
    if (!inside || (x - h >= lo && x + h <= hi)) {
        d = (param_line_point(object, along_u, x + h, held) - param_line_point(object, along_u, x - h, held)) / (2.0 * h);
    } else if (x + 2.0 * h <= hi) {
        d = (param_line_point(object, along_u, x, held) * -3.0 + param_line_point(object, along_u, x + h, held) * 4.0
             - param_line_point(object, along_u, x + 2.0 * h, held)) / (2.0 * h);
    } else if (x - 2.0 * h >= lo) {
        d = (param_line_point(object, along_u, x, held) * 3.0 - param_line_point(object, along_u, x - h, held) * 4.0
             + param_line_point(object, along_u, x - 2.0 * h, held)) / (2.0 * h);
    } else {
        d = vec3(0.0);
        return false;
    }
    return param_finite(d);
}

float param_nudge_inside(float x, float lo, float hi, float by) {
    return x - lo <= hi - x ? x + by : x - by;
}

vec3 param_world_normal(uint object, float u, float v) {
    vec4 dom = param_objects[object].domain;
    float u_range = dom.y - dom.x;
    float v_range = dom.w - dom.z;
    vec3 du;
    vec3 dv;
    if (!param_derivative(object, true, v, u, dom.x, dom.y, u_range / 1024.0, du)
        || !param_derivative(object, false, u, v, dom.z, dom.w, v_range / 1024.0, dv)) {
        return vec3(0.0);
    }
    if (length(dv) < 1e-3 * length(du)) {
        float u_in = param_nudge_inside(u, dom.x, dom.y, u_range / 256.0);
        if (!param_derivative(object, false, u_in, v, dom.z, dom.w, v_range / 32.0, dv)) {
            return vec3(0.0);
        }
    } else if (length(du) < 1e-3 * length(dv)) {
        float v_in = param_nudge_inside(v, dom.z, dom.w, v_range / 256.0);
        if (!param_derivative(object, true, v_in, u, dom.x, dom.y, u_range / 32.0, du)) {
            return vec3(0.0);
        }
    }
    vec3 n = cross(du, dv);
    float scale = length(du) * length(dv);
    if (!param_finite(n) || length(n) <= 1e-6 * scale || scale == 0.0) {
        return vec3(0.0);
    }
    return normalize(n);
}

#endif
