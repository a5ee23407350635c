// The scene every parametric-objects pass reads: one ParamObject per object, the objects' float
// parameters (SH coefficients, ...) and the SH recurrence table. Bindings 0-2 in every pass.
// Layouts are documented in param/scene.rs (GpuObject), which a test holds to this one.
// PARAM_KIND_* and PARAM_FLAG_* come from Rust as defines.

#ifndef PARAM_SCENE_GLSL
#define PARAM_SCENE_GLSL

struct ParamObject {
    vec4 model[3];    // rows of the 3x4 object-to-world matrix
    vec4 colour;      // base colour (rgb)
    vec4 domain;      // u0, u1, v0, v1
    vec4 radius_map;  // SH glyphs: radius' = clamp(r * x + y, z, w)
    uint kind;        // PARAM_KIND_*
    uint params;      // index of the object's first value in param_values
    uint order;       // SH order
    uint flags;       // PARAM_FLAG_* | SH basis << PARAM_BASIS_SHIFT
};

layout(binding = 0, std430) readonly buffer ParamObjects { ParamObject param_objects[]; };
layout(binding = 1, std430) readonly buffer ParamValues { float param_values[]; };
layout(binding = 2, std430) readonly buffer ShRecurrence { vec2 sh_recurrence[]; };

#endif
