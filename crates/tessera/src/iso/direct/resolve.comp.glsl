#version 460
// Turns the compute rasterizer's depth|triangle frame into colour: each pixel interpolates its
// triangle's attributes with perspective-correct barycentrics and is shaded like a fragment of
// the mesh-shader path.
//
// With TWO_LISTS defined (occlusion culling) the frame holds triangles of two lists: indices
// below params.size.z are the first list's, the rest the second's (drawn with that index base).
// Each drawn pixel then also flags its triangle's block as seen (bit 0 of the block's flags).
//
// A workgroup takes RESOLVE_PIXELS × 64 pixels of one row, invocation i the pixels i, i + 64,
// ..., so every load of the frame and store of the pixels is contiguous across a workgroup: the
// pass streams 12 bytes a pixel, which 8×8 tiles of one pixel per invocation moved at 1.0 TB/s
// on an H200 and rows move at 2.1 TB/s. RESOLVE_PIXELS comes from raster::RESOLVE_PIXELS.
#include "raster/raster.glsl"
#include "common/shading.glsl"
#include "iso/direct/attributes.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer Frame { uvec2 depth_payload[]; };
layout(binding = 1) readonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = 2) readonly buffer Attributes { TriangleAttributes attributes[]; };
layout(binding = 3) writeonly buffer Pixels { uint pixels[]; };
#ifdef TWO_LISTS
layout(binding = 4) readonly buffer SecondTriangles { RasterTriangle second_triangles[]; };
layout(binding = 5) readonly buffer SecondAttributes { TriangleAttributes second_attributes[]; };
layout(binding = 6) buffer BlockFlags { uint block_flags[]; };
#endif

layout(push_constant) uniform ResolveParams {
    vec4 eye_world;
    vec4 light;   // xyz towards the light, world space
    uvec4 size;   // x width, y height, z first index of the second list (TWO_LISTS)
} params;

void resolve_pixel(uvec2 pixel, uvec2 size) {
    uint i = pixel.y * size.x + pixel.x;
    uvec2 value = depth_payload[i];
    vec4 colour = BACKGROUND;
    if (!raster_is_empty(value)) {
        uint t = raster_index(value);
        RasterTriangle tri;
        TriangleAttributes a;
#ifdef TWO_LISTS
        if (t >= params.size.z) {
            tri = second_triangles[t - params.size.z];
            a = second_attributes[t - params.size.z];
        } else {
            tri = triangles[t];
            a = attributes[t];
        }
        uint block = floatBitsToUint(a.normal_world[0].w);
        if (block < uint(block_flags.length())) {
            block_flags[block] = 1u;  // every writer stores the same value
        }
#else
        tri = triangles[t];
        a = attributes[t];
#endif
        vec3 b = raster_barycentrics(tri.clip[0], tri.clip[1], tri.clip[2], raster_pixel_centre(pixel), size);
        vec3 normal = b.x * a.normal_world[0].xyz + b.y * a.normal_world[1].xyz + b.z * a.normal_world[2].xyz;
        vec3 position = b.x * a.position_world[0].xyz + b.y * a.position_world[1].xyz + b.z * a.position_world[2].xyz;
        colour = vec4(shade_surface(normal, position, params.eye_world.xyz, params.light.xyz), 1.0);
    }
    pixels[i] = packUnorm4x8(colour);
}

void main() {
    uvec2 size = params.size.xy;
    uint y = gl_WorkGroupID.y;
    uint first = gl_WorkGroupID.x * (RESOLVE_PIXELS * gl_WorkGroupSize.x) + gl_LocalInvocationID.x;
    for (uint k = 0u; k < RESOLVE_PIXELS; ++k) {
        uint x = first + k * gl_WorkGroupSize.x;
        if (x < size.x && y < size.y) {
            resolve_pixel(uvec2(x, y), size);
        }
    }
}
