#version 460
// The per-pixel arithmetic on the compute path: one invocation per pixel, stored into an image of
// the same format the fragment twin (busy.frag.glsl) renders into.
#include "common/throughput.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba8) uniform writeonly image2D target;

layout(push_constant) uniform ArithmeticParams {
    uvec2 size;       // target width, height
    uint iterations;  // busy_work loop count
} params;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    vec2 uv = (vec2(pixel) + 0.5) / vec2(params.size);
    imageStore(target, ivec2(pixel), busy_work(uv, params.iterations));
}
