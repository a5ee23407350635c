#version 460
// Places each vertex the tessellator made at f(u, v) of its patch (paper E §4.2): (u, v) from
// gl_TessCoord over the patch's ranges, the range ends taken exactly so that neighbouring
// patches' shared corners and edges meet.
#include "param/functions.glsl"
#include "param/tess_params.glsl"

layout(quads, equal_spacing, ccw) in;

layout(location = 0) patch in vec4 tc_range;
layout(location = 1) patch in uint tc_object;
layout(location = 0) out vec2 te_uv;
layout(location = 1) flat out uint te_object;
#ifdef TESS_DEBUG_LEVELS
layout(location = 2) flat out vec2 te_inner;
#endif

float range_param(vec2 r, float t) {
    return t == 0.0 ? r.x : (t == 1.0 ? r.y : r.x + (r.y - r.x) * t);
}

void main() {
    float u = range_param(tc_range.xy, gl_TessCoord.x);
    float v = range_param(tc_range.zw, gl_TessCoord.y);
    vec3 p = param_world_position(tc_object, u, v);
    gl_Position = params.world_to_clip * vec4(p, 1.0);
    te_uv = vec2(u, v);
    te_object = tc_object;
#ifdef TESS_DEBUG_LEVELS
    te_inner = vec2(gl_TessLevelInner[0], gl_TessLevelInner[1]);
#endif
}
