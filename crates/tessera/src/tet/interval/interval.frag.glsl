#version 460
// Adds the tet's optical depth along this pixel's ray: the world-space length between the
// front and back faces (from their interpolated inverse view depths) times its absorption.
#include "tet/interval/params.glsl"

layout(location = 0) in vec2 inverse_depths;
layout(location = 1) flat in vec3 tet_absorption;
layout(location = 0) out vec4 optical_depth;

void main() {
    float front = 1.0 / inverse_depths.x;
    float back = 1.0 / inverse_depths.y;
    // The view-space ray through the pixel centre has forward component 1; its length turns a
    // depth difference into a distance.
    vec2 ndc = 2.0 * gl_FragCoord.xy / vec2(params.counts.yz) - 1.0;
    vec2 slope = vec2(ndc.x * params.view.x, -ndc.y * params.view.y);
    float length_world = abs(back - front) * sqrt(1.0 + dot(slope, slope));
    optical_depth = vec4(length_world * tet_absorption, 0.0);
}
