// Push constants of the param-tess drawing stages (TessParams in param/tess.rs, whose layout a
// test holds to this one).

#ifndef PARAM_TESS_PARAMS_GLSL
#define PARAM_TESS_PARAMS_GLSL

layout(push_constant) uniform TessParams {
    mat4 world_to_clip;
    vec4 eye;                  // world space
    vec4 light;                // unit direction towards the light
    vec2 viewport;             // raster width, height in pixels
    float pixels_per_segment;  // adaptive levels: screen length one segment should span
    float fixed_level;         // > 0: every level is this; 0: adaptive
    float min_level;           // adaptive levels are clamped to [min_level, max_level]
    float max_level;
    uint render_capacity;      // patches the render list holds
    uint patches_per_instance; // patches one instance of the draw holds (param/tess.rs)
} params;

#endif
