// Push constants of the LOD passes (LodParams in param/lod.rs).

#ifndef PARAM_LOD_PARAMS_GLSL
#define PARAM_LOD_PARAMS_GLSL

layout(push_constant) uniform LodParams {
    mat4 world_to_clip;
    vec2 viewport;          // raster width, height in pixels
    vec2 thresholds;        // t_u, t_v in raster pixels
    uint step;              // this LOD step, 0-based
    uint last;              // 1 in the last step: split patches are rendered anyway
    uint eval_capacity;     // patches each evaluation list holds
    uint render_capacity;   // patches the render list holds
    uint culling;           // 1: drop patches whose samples all lie outside one frustum side
    uint capture_capacity;  // samples the debug capture holds (0: off)
    uint object_count;
    uint pre_split;         // each object starts as pre_split × pre_split patches
} params;

#endif
