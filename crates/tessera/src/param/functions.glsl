// The parametric surfaces f(u, v), mirroring tessera_data::param::functions, ::glyph, ::seashell
// and ::yarn. Adding a function: one GLSL function here, one case in param_position, one arm in
// param/scene.rs.

#ifndef PARAM_FUNCTIONS_GLSL
#define PARAM_FUNCTIONS_GLSL

#include "param/scene.glsl"
#include "param/sh.glsl"
// The user's `vec3 f(float u, float v)` as param_user_function (param/user.rs); a stub
// returning the origin where there is none.
#include "param/user_function.glsl"

const float PARAM_PI = 3.14159265358979;

// Unit sphere, z up: u = polar angle from +z, v = azimuth.
vec3 param_sphere(float u, float v) {
    float su = sin(u);
    return vec3(su * cos(v), su * sin(v), cos(u));
}

// "Johi's Heart" (paper E, Listing 1) from the authors' released shader's sphere, as the CPU.
vec3 param_heart(float u, float v) {
    float su = sin(u);
    vec3 p = vec3(su * cos(v), cos(u), su * sin(v));
    if (u < PARAM_PI / 2.0) {
        p.y *= 1.0 - cos(sqrt(sqrt(abs(p.x * PARAM_PI * 0.7)))) * 0.8;
    } else {
        p.x *= su * su;
    }
    return p * vec3(0.9, 1.0, 0.4);
}

// SH glyph: the sphere direction scaled by the normalised SH radius (radius_map from the CPU's
// normalisation range, never recomputed here).
float param_glyph_radius(ParamObject o, float u, float v) {
    uint basis = (o.flags >> PARAM_BASIS_SHIFT) & 3u;
    float r = sh_evaluate(o.params, o.order, basis, u, v);
    return clamp(r * o.radius_map.x + o.radius_map.y, o.radius_map.z, o.radius_map.w);
}

vec3 param_sh_glyph(ParamObject o, float u, float v) {
    return param_sphere(u, v) * param_glyph_radius(o, u, v);
}

// Seashell (tessera_data::param::seashell), operation for operation in f32. What depends on
// the parameters alone (cot α, sin β, the tilt, the nodules' offsets, periods and exponents) comes
// from encode_function, computed there by the CPU's own f32 expressions, so only the
// (u, v)-dependent operations can round differently here. Layout at o.params (23 values):
// cot α, A, sin β, -cos β, scale, a, b, the tilt's columns (9), then per nodule direction
// (around, along) its offset, period 2π/N and -(W/N)^k, and last (H_s/20)(H_θ/20).
float param_nodule(float angle, uint at) {
    float t = (angle - param_values[at]) / param_values[at + 1u];
    // Rust's round takes halves away from zero; GLSL leaves halves to the implementation.
    // t - trunc(t) is exact, so this is Rust's rounding exactly.
    float r = trunc(t);
    if (abs(t - r) >= 0.5) {
        r += sign(t);
    }
    float f = t - r;
    return exp(param_values[at + 2u] * f * f);
}

vec3 param_seashell(ParamObject o, float u, float v) {
    uint at = o.params;
    float theta = u;
    float s = v;
    float spiral_start = param_values[at + 1u];
    float scale = param_values[at + 4u];
    float radius = spiral_start * exp(theta * param_values[at]);
    float sin_t = sin(theta);
    float cos_t = cos(theta);
    float sin_b = param_values[at + 2u];
    vec3 centre = vec3(sin_b * sin_t, sin_b * cos_t, param_values[at + 3u]) * (radius * scale);

    float sin_s = sin(s);
    float cos_s = cos(s);
    // tilt * (0, b cos s, a sin s), summed column by column as glam's Mat3 * Vec3 (the first
    // column's product is zero).
    vec3 col1 = vec3(param_values[at + 10u], param_values[at + 11u], param_values[at + 12u]);
    vec3 col2 = vec3(param_values[at + 13u], param_values[at + 14u], param_values[at + 15u]);
    vec3 w = col1 * (param_values[at + 6u] * cos_s) + col2 * (param_values[at + 5u] * sin_s);
    // Rz(-θ) * w with sin(-θ) = -sin θ, as the CPU's odd sine gives; its zero entries add
    // nothing.
    vec3 turned = vec3(cos_t * w.x + sin_t * w.y, -sin_t * w.x + cos_t * w.y, w.z);

    float around = param_nodule(s, at + 16u);
    float along = param_nodule(theta, at + 19u);
    float bump = param_values[at + 22u] * around * along;

    vec3 p = centre + turned * (radius / spiral_start * scale * (1.0 + bump));
    return p.xzy;
}

// Knit yarn tube (tessera_data::param::yarn, which computes in f64), operation for operation in
// f32. Layout at o.params (8 values): roundness a, height h, depth d, yarn radius r, twist ω,
// 1 for a fibre (0 for the yarn), the fibre's phase φ, the tube radius.
vec3 param_unit_or_x(vec3 d) {
    float rcp = 1.0 / length(d);
    return (rcp > 0.0 && !isinf(rcp) && !isnan(rcp)) ? d * rcp : vec3(1.0, 0.0, 0.0);
}

// normalize(t.y, -t.x, 0) made orthogonal to t (x where t is parallel to z).
vec3 param_orthogonal(vec3 t) {
    vec3 flat_ = vec3(t.y, -t.x, 0.0);
    vec3 seed = dot(flat_, flat_) > 1e-18 ? flat_ : vec3(1.0, 0.0, 0.0);
    return normalize(seed - t * dot(seed, t));
}

// Rodrigues' rotation of x about the unit axis by angle.
vec3 param_rotate_about(vec3 x, vec3 axis, float angle) {
    float s = sin(angle);
    float c = cos(angle);
    return x * c + cross(axis, x) * s + axis * (dot(axis, x) * (1.0 - c));
}

vec3 param_yarn(ParamObject o, float u, float v) {
    uint at = o.params;
    float a = param_values[at];
    float h = param_values[at + 1u];
    float d = param_values[at + 2u];
    float t = u;
    float s1 = sin(t);
    float c1 = cos(t);
    float s2 = sin(2.0 * t);
    float c2 = cos(2.0 * t);
    vec3 centre = vec3(t + a * s2, h * c1, d * c2);
    vec3 velocity = vec3(1.0 + 2.0 * a * c2, -h * s1, -2.0 * d * s2);
    if (param_values[at + 5u] != 0.0) {
        float r = param_values[at + 3u];
        float twist = param_values[at + 4u];
        vec3 acc = vec3(-4.0 * a * s2, -h * c1, -4.0 * d * c2);
        vec3 jerk = vec3(-8.0 * a * c2, h * s1, 8.0 * d * s2);
        // KnitParams::frenet_frame.
        vec3 tangent = param_unit_or_x(velocity);
        vec3 bend = acc - velocity * (dot(velocity, acc) / dot(velocity, velocity));
        float bend_rcp = 1.0 / length(bend);
        vec3 normal = (bend_rcp > 0.0 && !isinf(bend_rcp) && !isnan(bend_rcp))
            ? bend * bend_rcp : param_orthogonal(tangent);
        vec3 binormal = cross(tangent, normal);
        float angle = t * twist - 2.0 * c1 + param_values[at + 6u];
        float sin_a = sin(angle);
        float cos_a = cos(angle);
        // KnitParams::fiber_velocity, before the centre moves onto the fibre.
        vec3 turning = cross(velocity, acc);
        float turning2 = dot(turning, turning);
        float speed = length(velocity);
        float curving = 0.0;
        float twisting = 0.0;
        if (turning2 > 0.0 && !isinf(turning2)) {
            curving = sqrt(turning2) / dot(velocity, velocity);
            twisting = speed * dot(turning, jerk) / turning2;
        }
        float turn = twist + 2.0 * s1;
        velocity = tangent * (speed - r * curving * cos_a)
            + (binormal * cos_a - normal * sin_a) * (r * (turn + twisting));
        centre += (normal * cos_a + binormal * sin_a) * r;
    }
    vec3 tangent = param_unit_or_x(velocity);
    vec3 spoke = param_rotate_about(param_orthogonal(tangent), tangent, v);
    return centre + spoke * param_values[at + 7u];
}

// f(u, v) of object `object` in its own space.
vec3 param_position(uint object, float u, float v) {
    ParamObject o = param_objects[object];
    switch (o.kind) {
    case PARAM_KIND_SPHERE:
        return param_sphere(u, v);
    case PARAM_KIND_HEART:
        return param_heart(u, v);
    case PARAM_KIND_SH_GLYPH:
        return param_sh_glyph(o, u, v);
    case PARAM_KIND_USER:
        return param_user_function(u, v);
    case PARAM_KIND_SEASHELL:
        return param_seashell(o, u, v);
    case PARAM_KIND_YARN:
        return param_yarn(o, u, v);
    default:
        return vec3(0.0);
    }
}

vec3 param_to_world(uint object, vec3 p) {
    vec4 h = vec4(p, 1.0);
    return vec3(dot(param_objects[object].model[0], h), dot(param_objects[object].model[1], h),
                dot(param_objects[object].model[2], h));
}

vec3 param_world_position(uint object, float u, float v) {
    return param_to_world(object, param_position(object, u, v));
}

// Unshaded colour: |direction| from the glyph centre for glyphs (mid grey at the centre), the
// object's colour otherwise (tessera_data::param::reference::base_colour).
// The same for the object-space point p of the object.
vec3 param_colour_at(uint object, vec3 p) {
    if ((param_objects[object].flags & PARAM_FLAG_DIRECTION_COLOUR) != 0u) {
        float len = length(p);
        return len > 0.0 ? abs(p / len) : vec3(0.5);
    }
    return param_objects[object].colour.rgb;
}

vec3 param_base_colour(uint object, float u, float v) {
    if ((param_objects[object].flags & PARAM_FLAG_DIRECTION_COLOUR) != 0u) {
        return param_colour_at(object, param_position(object, u, v));
    }
    return param_objects[object].colour.rgb;
}

#endif
