#version 460
// Adds the tet's optical depth along this pixel's ray: the world-space length between the
// front and back faces (from their interpolated inverse view depths) times its absorption.
#include "tet/interval/params.glsl"
#include "tet/interval/length.glsl"

layout(location = 0) in vec2 inverse_depths;
layout(location = 1) flat in vec3 tet_absorption;
layout(location = 0) out vec4 optical_depth;

void main() {
    vec2 ndc = 2.0 * gl_FragCoord.xy / vec2(params.counts.yz) - 1.0;
    optical_depth = vec4(interval_length(inverse_depths, ndc) * tet_absorption, 0.0);
}
