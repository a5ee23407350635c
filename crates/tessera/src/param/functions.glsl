// The parametric surfaces f(u, v), mirroring tessera_data::param::functions and ::glyph. Adding
// a function: one GLSL function here, one case in param_position, one arm in param/scene.rs.

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
vec3 param_base_colour(uint object, float u, float v) {
    if ((param_objects[object].flags & PARAM_FLAG_DIRECTION_COLOUR) != 0u) {
        vec3 p = param_position(object, u, v);
        float len = length(p);
        return len > 0.0 ? abs(p / len) : vec3(0.5);
    }
    return param_objects[object].colour.rgb;
}

#endif
