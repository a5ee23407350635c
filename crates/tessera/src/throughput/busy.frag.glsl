#version 460
// The per-pixel arithmetic on the graphics path: one fragment per pixel of the full-screen
// triangle. busy.comp.glsl is its compute twin.
#include "common/throughput.glsl"

layout(push_constant) uniform ArithmeticParams {
    uvec2 size;       // target width, height
    uint iterations;  // busy_work loop count
} params;

layout(location = 0) out vec4 color;

void main() {
    // gl_FragCoord is the pixel centre, the same point the compute twin evaluates.
    color = busy_work(gl_FragCoord.xy / vec2(params.size), params.iterations);
}
