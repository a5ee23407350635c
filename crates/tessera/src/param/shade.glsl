// Shading of a surface point of a parametric object, tessera_data::param::reference::shade:
// base colour (by direction for glyphs) times ambient + two-sided Lambert, the normal turned
// towards the eye (a degenerate normal faces the eye). The normal: SH glyphs' from the series'
// derivatives where they are regular, otherwise (and for every other function) by finite
// differences as on the CPU.
// SHADE_AMBIENT and SHADE_DIFFUSE come from Rust (param/points.rs, points_defines).

#ifndef PARAM_SHADE_GLSL
#define PARAM_SHADE_GLSL

#include "param/normal.glsl"

vec3 param_shade(uint object, float u, float v, vec3 eye, vec3 light) {
    vec3 local;
    vec3 n;
    vec3 position;
    vec3 base;
    // A glyph's point, normal and colour from one evaluation of its SH series with derivatives.
    if (param_objects[object].kind == PARAM_KIND_SH_GLYPH && param_glyph_surface(object, u, v, local, n)) {
        position = param_to_world(object, local);
        base = param_colour_at(object, local);
    } else {
        position = param_world_position(object, u, v);
        n = param_difference_normal(object, u, v);
        base = param_base_colour(object, u, v);
    }
    vec3 view = normalize(eye - position);
    if (n == vec3(0.0)) {
        n = view;
    }
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    return base * (SHADE_AMBIENT + SHADE_DIFFUSE * max(dot(n, light), 0.0));
}

#endif
