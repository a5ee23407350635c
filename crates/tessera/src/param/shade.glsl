// Shading of a surface point of a parametric object, tessera_data::param::reference::shade:
// base colour (by direction for glyphs) times ambient + two-sided Lambert, the normal from the
// function by finite differences and turned towards the eye; a degenerate normal faces the eye.
// SHADE_AMBIENT and SHADE_DIFFUSE come from Rust (param/points.rs, points_defines).

#ifndef PARAM_SHADE_GLSL
#define PARAM_SHADE_GLSL

#include "param/normal.glsl"

vec3 param_shade(uint object, float u, float v, vec3 eye, vec3 light) {
    vec3 position = param_world_position(object, u, v);
    vec3 n = param_world_normal(object, u, v);
    vec3 view = normalize(eye - position);
    if (n == vec3(0.0)) {
        n = view;
    }
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    return param_base_colour(object, u, v) * (SHADE_AMBIENT + SHADE_DIFFUSE * max(dot(n, light), 0.0));
}

#endif
