#version 460
// Adds what the tet contributes along this pixel's ray (integrand.glsl) to the float target:
// additive blending, or maximum blending for INTEGRAND_MAXIMUM.
#include "tet/interval/buffers.glsl"
#include "tet/interval/params.glsl"
#include "tet/interval/length.glsl"
#include "tet/interval/table.glsl"
#include "tet/interval/integrand.glsl"

layout(location = 0) in vec4 interval_attrs;
layout(location = 1) flat in vec3 tet_absorption;
layout(location = 0) out vec4 accumulated;

void main() {
    vec2 ndc = 2.0 * gl_FragCoord.xy / vec2(params.counts.yz) - 1.0;
    accumulated = vec4(integrand(interval_attrs, ndc, tet_absorption), 0.0);
}
