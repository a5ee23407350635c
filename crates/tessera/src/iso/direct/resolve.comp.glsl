#version 460
// Turns the compute rasterizer's depth|triangle frame into colour: each pixel interpolates its
// triangle's attributes with perspective-correct barycentrics and is shaded like a fragment of
// the mesh-shader path.
#include "raster/raster.glsl"
#include "common/shading.glsl"
#include "iso/direct/attributes.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) readonly buffer Frame { uvec2 depth_payload[]; };
layout(binding = 1) readonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = 2) readonly buffer Attributes { TriangleAttributes attributes[]; };
layout(binding = 3) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform ResolveParams {
    vec4 eye_world;
    vec4 light;   // xyz towards the light, world space
    uvec4 size;   // x width, y height
} params;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uvec2 size = params.size.xy;
    if (any(greaterThanEqual(pixel, size))) {
        return;
    }
    uint i = pixel.y * size.x + pixel.x;
    uvec2 value = depth_payload[i];
    vec4 colour = BACKGROUND;
    if (!raster_is_empty(value)) {
        uint t = raster_index(value);
        RasterTriangle tri = triangles[t];
        vec3 b = raster_barycentrics(tri.clip[0], tri.clip[1], tri.clip[2], raster_pixel_centre(pixel), size);
        TriangleAttributes a = attributes[t];
        vec3 normal = b.x * a.normal_world[0].xyz + b.y * a.normal_world[1].xyz + b.z * a.normal_world[2].xyz;
        vec3 position = b.x * a.position_world[0].xyz + b.y * a.position_world[1].xyz + b.z * a.position_world[2].xyz;
        colour = vec4(shade_surface(normal, position, params.eye_world.xyz, params.light.xyz), 1.0);
    }
    pixels[i] = packUnorm4x8(colour);
}
