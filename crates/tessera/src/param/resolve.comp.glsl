#version 460
// Shades the point pass's depth|payload raster into colour: each image pixel averages its k x k
// raster samples (k = supersampling), each sample re-evaluating its object at the stored (u, v):
// world position, normal (param/shade.glsl) and base colour, two-sided Lambert + ambient
// (tessera_data::param::reference::shade), background where nothing was drawn.
#include "raster/raster.glsl"
#include "param/shade.glsl"
#include "param/payload.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3, std430) readonly buffer Frame { uvec2 depth_payload[]; };
layout(binding = 4, std430) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform ResolveParams {
    vec4 eye;         // world space
    vec4 light;       // unit direction towards the light
    vec4 background;  // rgb
    uvec2 size;       // image width, height
    uint supersample; // raster samples per image pixel along each axis
    uint uv_bits;     // payload bits per parameter
} params;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    uint k = params.supersample;
    uint raster_width = params.size.x * k;
    vec3 sum = vec3(0.0);
    for (uint sy = 0u; sy < k; ++sy) {
        for (uint sx = 0u; sx < k; ++sx) {
            uvec2 value = depth_payload[(pixel.y * k + sy) * raster_width + pixel.x * k + sx];
            if (raster_is_empty(value)) {
                sum += params.background.rgb;
            } else {
                uint object;
                float u;
                float v;
                param_unpack(raster_index(value), params.uv_bits, object, u, v);
                sum += param_shade(object, u, v, params.eye.xyz, params.light.xyz);
            }
        }
    }
    pixels[pixel.y * params.size.x + pixel.x] = packUnorm4x8(vec4(sum / float(k * k), 1.0));
}
