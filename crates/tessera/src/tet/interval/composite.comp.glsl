#version 460
// The post pass of interval shading: turns what the pixels accumulated into colour.
//   absorption  background light crossing the optical depth keeps exp(-depth) per channel
//               (Beer–Lambert)
//   emission    background plus the emitted light
//   maximum     the table's colour at the largest scalar, background where no tet was crossed
//   sdf         the nearest asteroid's colour, background where none was hit
// The accumulation is an RGBA32F image (graphics path) or, on the compute path (SOURCE_BUFFER),
// a buffer laid out by optical_layout.glsl, or for the asteroid field
// two 64-bit words per pixel.
layout(local_size_x = 8, local_size_y = 8) in;
#if SOURCE_BUFFER && INTEGRAND == INTEGRAND_SDF
layout(binding = 0) readonly buffer Accumulated { uvec4 accumulated[]; };
#elif SOURCE_BUFFER
layout(binding = 0) readonly buffer Accumulated { float accumulated[]; };
#else
layout(binding = 0, rgba32f) uniform readonly image2D accumulated;
#endif
layout(binding = 1) writeonly buffer Pixels { uint pixels[]; };
layout(binding = 2) readonly buffer Table { vec4 table[]; };

#include "tet/interval/table.glsl"
#include "tet/interval/optical_layout.glsl"

layout(push_constant) uniform CompositeParams {
    vec4 background;
    uvec4 size;
} params;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size.xy))) {
        return;
    }
    vec3 background = params.background.rgb;
#if SOURCE_BUFFER && INTEGRAND == INTEGRAND_SDF
    uvec2 nearest = accumulated[pixel.y * params.size.x + pixel.x].xy;  // colour, depth bits
    vec3 light = nearest.y == 0xffffffffu ? background : unpackUnorm4x8(nearest.x).rgb;
#else
#if SOURCE_BUFFER
    uint index = pixel.y * params.size.x + pixel.x;
    uint count = params.size.x * params.size.y;
    vec4 value = vec4(accumulated[optical_index(index, 0u, count)], accumulated[optical_index(index, 1u, count)],
                      accumulated[optical_index(index, 2u, count)], 0.0);
#else
    vec4 value = imageLoad(accumulated, ivec2(pixel));
#endif
#if INTEGRAND == INTEGRAND_SDF
    vec3 light = value.a > 0.0 ? value.rgb : background;
#elif INTEGRAND == INTEGRAND_MAXIMUM
    vec3 light = value.g > 0.0 ? table_value(value.r) : background;
#elif INTEGRAND == INTEGRAND_EMISSION
    vec3 light = background + value.rgb;
#else
    vec3 light = background * exp(-value.rgb);
#endif
#endif
    pixels[pixel.y * params.size.x + pixel.x] = packUnorm4x8(vec4(light, 1.0));
}
