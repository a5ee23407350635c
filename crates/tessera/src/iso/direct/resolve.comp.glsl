#version 460
// Turns the compute rasterizer's depth|triangle frame into colour: each pixel interpolates its
// triangle's attributes with perspective-correct barycentrics (its world position from the
// clip-space corners) and is shaded like a fragment of the mesh-shader path.
//
// With TWO_LISTS defined (occlusion culling) the frame holds triangles of two lists: indices
// below params.second_base are the first list's, the rest the second's (drawn with that index base).
// Each drawn pixel then also flags its triangle's block as seen (bit 0 of the block's flags);
// with SEEN_BLOCK_LIST defined (direct's culling) a block's flag is instead the number of the
// last frame it owned a pixel in, and the first pixel to find it older lists the block for the
// next frame's first pass (the list's dispatch is sized after this pass).
//
// Only the tiles the frame's raster passes marked with its number are read (raster/mod.rs); the
// rest are background. Each drawn pixel read is emptied again, so that the frame is empty for
// the next one without a fill of every pixel.
//
// A workgroup takes RESOLVE_PIXELS × 64 pixels of one row, invocation i the pixels i, i + 64,
// ..., so every load of the frame and store of the pixels is contiguous across a workgroup: the
// pass streams up to 12 bytes a pixel, which 8×8 tiles of one pixel per invocation moved at
// 1.0 TB/s on an H200 and rows move at 2.1 TB/s. RESOLVE_PIXELS and RASTER_TILE come from
// raster::RESOLVE_PIXELS and raster::RASTER_TILE.
#include "raster/raster.glsl"
#include "common/shading.glsl"
#include "iso/direct/attributes.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) buffer Frame { uvec2 depth_payload[]; };
layout(binding = 1) readonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = 2) readonly buffer Attributes { TriangleAttributes attributes[]; };
layout(binding = 3) writeonly buffer Pixels { uint pixels[]; };
#ifdef TWO_LISTS
layout(binding = 4) readonly buffer SecondTriangles { RasterTriangle second_triangles[]; };
layout(binding = 5) readonly buffer SecondAttributes { TriangleAttributes second_attributes[]; };
layout(binding = 6) buffer BlockFlags { uint block_flags[]; };
layout(binding = 7) readonly buffer TileFrames { uint tile_frames[]; };
#ifdef SEEN_BLOCK_LIST
#include "iso/direct/block_list.glsl"
layout(binding = 8) buffer NextBlocks { BlockListHeader next_list; uint next_blocks[]; };
#endif
#else
layout(binding = 4) readonly buffer TileFrames { uint tile_frames[]; };
#endif

layout(push_constant) uniform ResolveParams {
    mat4 clip_to_world;  // from the rasterizer's clip space to the world positions shaded
    vec4 eye_world;
    vec4 light;          // xyz towards the light, world space
    uvec2 size;          // width, height
    uint second_base;    // first index of the second list (TWO_LISTS)
    uint frame_number;   // the number the frame's raster passes marked their tiles with
    uint empties;        // 1: empty each drawn pixel read (0: the frame is kept for reading)
    uint seen_number;    // the number this frame writes into its blocks' flags (SEEN_BLOCK_LIST)
} params;

void resolve_pixel(uvec2 pixel, uvec2 size) {
    uint i = pixel.y * size.x + pixel.x;
    vec4 colour = BACKGROUND;
    uvec2 value = uvec2(RASTER_EMPTY_WORD);
    if (tile_frames[raster_tile_index(pixel, size.x)] == params.frame_number) {
        value = depth_payload[i];
    }
    if (!raster_is_empty(value)) {
        if (params.empties != 0u) {
            depth_payload[i] = uvec2(RASTER_EMPTY_WORD);
        }
        uint t = raster_index(value);
        RasterTriangle tri;
        TriangleAttributes a;
#ifdef TWO_LISTS
        if (t >= params.second_base) {
            tri = second_triangles[t - params.second_base];
            a = second_attributes[t - params.second_base];
        } else {
            tri = triangles[t];
            a = attributes[t];
        }
        uint block = a.corners[0].maker;
        if (block < uint(block_flags.length())) {
#ifdef SEEN_BLOCK_LIST
            uint seen = params.seen_number;
            if (block_flags[block] != seen && atomicExchange(block_flags[block], seen) != seen) {
                next_blocks[atomicAdd(next_list.count, 1u)] = block;
            }
#else
            block_flags[block] = 1u;  // every writer stores the same value
#endif
        }
#else
        tri = triangles[t];
        a = attributes[t];
#endif
        vec3 b = raster_barycentrics(tri.clip[0], tri.clip[1], tri.clip[2], raster_pixel_centre(pixel), size);
        vec3 normal = b.x * a.corners[0].normal_world + b.y * a.corners[1].normal_world + b.z * a.corners[2].normal_world;
        // Clip space is linear in world space, so the clip point the weights pick is the clip
        // point of the world point they pick.
        vec4 clip = b.x * tri.clip[0] + b.y * tri.clip[1] + b.z * tri.clip[2];
        vec4 world = params.clip_to_world * clip;
        vec3 position = world.xyz / world.w;
        colour = vec4(shade_surface(normal, position, params.eye_world.xyz, params.light.xyz), 1.0);
    }
    pixels[i] = packUnorm4x8(colour);
}

void main() {
    uvec2 size = params.size;
    uint y = gl_WorkGroupID.y;
    uint first = gl_WorkGroupID.x * (RESOLVE_PIXELS * gl_WorkGroupSize.x) + gl_LocalInvocationID.x;
    for (uint k = 0u; k < RESOLVE_PIXELS; ++k) {
        uint x = first + k * gl_WorkGroupSize.x;
        if (x < size.x && y < size.y) {
            resolve_pixel(uvec2(x, y), size);
        }
    }
}
