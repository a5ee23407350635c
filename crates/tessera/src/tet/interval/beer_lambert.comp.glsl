#version 460
// The post pass of interval shading: light of colour `background` crossing the accumulated
// optical depth keeps exp(-depth) of itself per channel (Beer–Lambert).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform readonly image2D optical_depth;
layout(binding = 1) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform CompositeParams {
    vec4 background;
    uvec4 size;
} params;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size.xy))) {
        return;
    }
    vec3 depth = imageLoad(optical_depth, ivec2(pixel)).rgb;
    vec3 light = params.background.rgb * exp(-depth);
    pixels[pixel.y * params.size.x + pixel.x] = packUnorm4x8(vec4(light, 1.0));
}
