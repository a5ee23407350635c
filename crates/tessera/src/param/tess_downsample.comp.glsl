#version 460
// The image from the (resolved) colour attachment: each pixel the average of its k x k raster
// pixels (k = supersampling; the reference averages the same samples), packed to RGBA8.

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba16f) readonly uniform image2D raster;
layout(binding = 1, std430) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform DownsampleParams {
    uvec2 size;        // image width, height
    uint supersample;  // raster pixels per image pixel along each axis
} params;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    uint k = params.supersample;
    vec3 sum = vec3(0.0);
    for (uint sy = 0u; sy < k; ++sy) {
        for (uint sx = 0u; sx < k; ++sx) {
            sum += imageLoad(raster, ivec2(pixel * k + uvec2(sx, sy))).rgb;
        }
    }
    pixels[pixel.y * params.size.x + pixel.x] = packUnorm4x8(vec4(sum / float(k * k), 1.0));
}
