#version 460
// sh-raytrace's image pass: per image pixel k x k rays (k = supersampling) through the raster
// sample centres, each traced through the glyph grid and shaded, or the background; the
// average goes to the packed RGBA8 pixel.
#include "param/raytrace_trace.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 7, std430) writeonly buffer Pixels { uint pixels[]; };

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    uint k = params.supersample;
    vec2 raster_size = vec2(params.size * k);
    vec3 sum = vec3(0.0);
    for (uint sy = 0u; sy < k; ++sy) {
        for (uint sx = 0u; sx < k; ++sx) {
            vec2 raster = vec2(pixel * k + uvec2(sx, sy)) + 0.5;
            vec3 dir = rt_camera_ray(raster, raster_size);
            float t;
            uint glyph = rt_trace(params.eye.xyz, dir, t);
            if (glyph == RT_NONE) {
                sum += params.background.rgb;
            } else {
                vec3 position = params.eye.xyz + t * dir;
                vec3 normal;
                vec3 colour;
                rt_surface(glyph, position, normal, colour);
                sum += rt_shade(normal, colour, position, params.eye.xyz, params.light.xyz);
            }
        }
    }
    pixels[pixel.y * params.size.x + pixel.x] = packUnorm4x8(vec4(sum / float(k * k), 1.0));
}
