// Unit normal of an object's world-space surface by finite differences, a port of
// tessera_data::param::functions::surface_normal (its step fractions and collapse ratio come as
// the PARAM_NORMAL_* defines; one-sided differences at the domain's edges).
// Returns vec3(0) where the CPU returns None.

#ifndef PARAM_NORMAL_GLSL
#define PARAM_NORMAL_GLSL

#include "param/functions.glsl"

// Every call of param_world_position inlines every parametric function (SH series, seashell,
// yarn, the user's f): drivers inline all calls, and a normal written with one call per stencil
// point gave the point and tessellation shaders ~66 copies, which took llvmpipe minutes to
// compile. So each function below reaches param_world_position through exactly one call site,
// in a loop whose trip count the compiler cannot know (and so does not unroll).

// The world point at parameter s along u (held = v) or along v (held = u).
vec3 param_line_point(uint object, bool along_u, float s, float held) {
    vec2 uv = along_u ? vec2(s, held) : vec2(held, s);
    return param_world_position(object, uv.x, uv.y);
}

bool param_finite(vec3 d) {
    return !any(isnan(d)) && !any(isinf(d));
}

const uint PARAM_STENCIL_CENTRAL = 0u;
const uint PARAM_STENCIL_FORWARD = 1u;
const uint PARAM_STENCIL_BACKWARD = 2u;

// Second-order difference along one parameter at x; false where the CPU gives None.
bool param_derivative(uint object, bool along_u, float held, float x, float lo, float hi, float h,
                      out vec3 d) {
    bool inside = x >= lo && x <= hi;
    uint stencil;
    float at[3];
    if (!inside || (x - h >= lo && x + h <= hi)) {
        stencil = PARAM_STENCIL_CENTRAL;
        at = float[3](x + h, x - h, x);
    } else if (x + 2.0 * h <= hi) {
        stencil = PARAM_STENCIL_FORWARD;
        at = float[3](x, x + h, x + 2.0 * h);
    } else if (x - 2.0 * h >= lo) {
        stencil = PARAM_STENCIL_BACKWARD;
        at = float[3](x, x - h, x - 2.0 * h);
    } else {
        d = vec3(0.0);
        return false;
    }
    uint count = stencil == PARAM_STENCIL_CENTRAL ? 2u : 3u;
    vec3 p[3];
    p[2] = vec3(0.0);
    for (uint i = 0u; i < count; ++i) {
        p[i] = param_line_point(object, along_u, at[i], held);
    }
    if (stencil == PARAM_STENCIL_CENTRAL) {
        d = (p[0] - p[1]) / (2.0 * h);
    } else if (stencil == PARAM_STENCIL_FORWARD) {
        d = (p[0] * -3.0 + p[1] * 4.0 - p[2]) / (2.0 * h);
    } else {
        d = (p[0] * 3.0 - p[1] * 4.0 + p[2]) / (2.0 * h);
    }
    return param_finite(d);
}

float param_nudge_inside(float x, float lo, float hi, float by) {
    return x - lo <= hi - x ? x + by : x - by;
}

// The world direction of object-space tangent t (the model's linear part).
vec3 param_tangent_to_world(uint object, vec3 t) {
    return vec3(dot(param_objects[object].model[0].xyz, t), dot(param_objects[object].model[1].xyz, t),
                dot(param_objects[object].model[2].xyz, t));
}

// SH glyphs: the object-space point and the world normal at (u, v) from one pass of the SH
// recurrence with its derivatives, instead of the four further evaluations of the differences.
// False where that normal is degenerate or a partial collapses (near the poles the azimuth's
// tangent vanishes), or where the radius is clamped (not differentiable at the clamp): the
// differences decide there, as on the CPU.
bool param_glyph_surface(uint object, float u, float v, out vec3 position, out vec3 normal) {
    ParamObject o = param_objects[object];
    uint basis = (o.flags >> PARAM_BASIS_SHIFT) & 3u;
    vec3 r = sh_evaluate_gradient(o.params, o.order, basis, u, v);
    float mapped = r.x * o.radius_map.x + o.radius_map.y;
    float radius = clamp(mapped, o.radius_map.z, o.radius_map.w);
    float su = sin(u);
    float cu = cos(u);
    float sv = sin(v);
    float cv = cos(v);
    vec3 direction = vec3(su * cv, su * sv, cu);  // param_sphere's, its sines shared below
    position = direction * radius;
    normal = vec3(0.0);
    if (radius != mapped) {
        return false;
    }
    vec3 along_u = vec3(cu * cv, cu * sv, -su) * radius + direction * (r.y * o.radius_map.x);
    vec3 along_v = vec3(-su * sv, su * cv, 0.0) * radius + direction * (r.z * o.radius_map.x);
    vec3 du = param_tangent_to_world(object, along_u);
    vec3 dv = param_tangent_to_world(object, along_v);
    // A partial the other dwarfs (near the poles) goes to the differences' nudged re-measure.
    if (!(length(dv) >= PARAM_NORMAL_COLLAPSE * length(du)
          && length(du) >= PARAM_NORMAL_COLLAPSE * length(dv))) {
        return false;
    }
    vec3 n = cross(du, dv);
    float scale = length(du) * length(dv);
    if (!param_finite(n) || length(n) <= 1e-6 * scale) {
        return false;
    }
    normal = normalize(n);
    return true;
}

// The normal by central differences (one-sided at the domain's edges), with the CPU's rules
// for collapsed partials.
vec3 param_difference_normal(uint object, float u, float v) {
    vec4 dom = param_objects[object].domain;
    float u_range = dom.y - dom.x;
    float v_range = dom.w - dom.z;
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    // Pass 0 measures du, pass 1 dv; pass 2 re-measures a collapsed partial on a line moved
    // PARAM_NORMAL_NUDGE of the other range into the domain, if one collapsed.
    for (uint pass = 0u; pass < 3u; ++pass) {
        bool along_u;
        float held;
        float h;
        if (pass == 0u) {
            along_u = true;
            held = v;
            h = u_range * PARAM_NORMAL_STEP;
        } else if (pass == 1u) {
            along_u = false;
            held = u;
            h = v_range * PARAM_NORMAL_STEP;
        } else if (length(dv) < PARAM_NORMAL_COLLAPSE * length(du)) {
            along_u = false;
            held = param_nudge_inside(u, dom.x, dom.y, u_range * PARAM_NORMAL_NUDGE);
            h = v_range * PARAM_NORMAL_NUDGE_STEP;
        } else if (length(du) < PARAM_NORMAL_COLLAPSE * length(dv)) {
            along_u = true;
            held = param_nudge_inside(v, dom.z, dom.w, v_range * PARAM_NORMAL_NUDGE);
            h = u_range * PARAM_NORMAL_NUDGE_STEP;
        } else {
            break;
        }
        vec2 range = along_u ? dom.xy : dom.zw;
        vec3 d;
        if (!param_derivative(object, along_u, held, along_u ? u : v, range.x, range.y, h, d)) {
            return vec3(0.0);
        }
        if (along_u) {
            du = d;
        } else {
            dv = d;
        }
    }
    vec3 n = cross(du, dv);
    float scale = length(du) * length(dv);
    if (!param_finite(n) || length(n) <= 1e-6 * scale || scale == 0.0) {
        return vec3(0.0);
    }
    return normalize(n);
}

vec3 param_world_normal(uint object, float u, float v) {
    vec3 position;
    vec3 normal;
    if (param_objects[object].kind == PARAM_KIND_SH_GLYPH
        && param_glyph_surface(object, u, v, position, normal)) {
        return normal;
    }
    return param_difference_normal(object, u, v);
}

#endif
