#version 460
// Adds what the tet contributes along this pixel's ray (integrand.glsl) to the float target:
// additive blending, or maximum blending for INTEGRAND_MAXIMUM. For INTEGRAND_SDF the fragment
// sphere-traces the tet's asteroid instead and the depth test keeps the nearest hit.
#include "tet/interval/buffers.glsl"
#include "tet/interval/params.glsl"
#include "tet/interval/length.glsl"
#include "tet/interval/table.glsl"
#include "tet/interval/integrand.glsl"
#if INTEGRAND == INTEGRAND_SDF
#include "tet/interval/sdf.glsl"
#endif

layout(location = 0) in vec4 interval_attrs;
layout(location = 1) flat in uint tet_id;
layout(location = 0) out vec4 accumulated;

void main() {
    vec2 ndc = 2.0 * gl_FragCoord.xy / vec2(params.counts.yz) - 1.0;
#if INTEGRAND == INTEGRAND_SDF
    vec4 hit = asteroid_hit(tet_id, interval_attrs, ndc, 1e30);
    if (hit.w < 0.0) {
        discard;
    }
    accumulated = vec4(hit.rgb, 1.0);
    gl_FragDepth = hit.w;
#else
    accumulated = vec4(integrand(interval_attrs, ndc, absorption[tet_id].rgb), 0.0);
#endif
}
