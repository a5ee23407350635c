#version 460
// Evaluates objects at given parameters, for tests and diagnostics: world position, the raw SH
// sum (glyphs; 0 otherwise), world normal and base colour.
#include "param/normal.glsl"

layout(local_size_x = 64) in;
struct Probe {
    uint object;
    float u;
    float v;
    uint pad;
};
struct ProbeResult {
    vec4 position;  // xyz world position, w raw SH sum
    vec4 normal;    // xyz world normal (0 where degenerate)
    vec4 colour;    // rgb base colour
};
layout(binding = 3, std430) readonly buffer Probes { Probe probes[]; };
layout(binding = 4, std430) writeonly buffer Results { ProbeResult results[]; };

layout(push_constant) uniform ProbeParams {
    uint count;
} params;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.count) {
        return;
    }
    Probe q = probes[i];
    ParamObject o = param_objects[q.object];
    float raw = 0.0;
    if (o.kind == PARAM_KIND_SH_GLYPH) {
        raw = sh_evaluate(o.params, o.order, (o.flags >> PARAM_BASIS_SHIFT) & 3u, q.u, q.v);
    }
    results[i] = ProbeResult(vec4(param_world_position(q.object, q.u, q.v), raw),
                             vec4(param_world_normal(q.object, q.u, q.v), 0.0),
                             vec4(param_base_colour(q.object, q.u, q.v), 1.0));
}
