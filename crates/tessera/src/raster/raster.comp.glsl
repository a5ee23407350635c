#version 460
// The compute rasterizer's pass: one invocation per clip-space triangle of a list, each drawn
// by raster/raster_draw.glsl (the CPU reference tessera_data::rasterize's rules); with
// RASTER_SUBGROUP_WALK, large ones by the invocation's whole subgroup.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_KHR_memory_scope_semantics : require
#if defined(RASTER_SUBGROUP_WALK) && RASTER_SUBGROUP_WALK
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#endif
#include "raster/raster.glsl"

layout(local_size_x = RASTER_GROUP_SIZE) in;
layout(binding = 0) readonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = 1) readonly buffer Counts {
    uint triangle_count;
    uint dispatch[3];
};
layout(binding = 2) buffer Frame { uint64_t depth_payload[]; };
// Per RASTER_TILE-square tile, the number of the last frame that drew into it (raster/mod.rs).
layout(binding = 3) writeonly buffer TileFrames { uint tile_frames[]; };

#include "raster/raster_draw.glsl"

layout(push_constant) uniform RasterParams {
    uvec2 size;     // frame width, height in pixels
    uint capacity;  // triangles the triangle buffer holds; later ones are never read
    uint index_base;  // added to each triangle's index in the frame (several buffers, one frame)
    uint frame_number;  // marked into every tile a triangle's pixel box reaches
    // 1: triangles of positive area on the snapped grid draw nothing; -1: those of negative
    // area; 0: both sides draw (tessera_data::rasterize::ScreenWinding, tessera_data::facing).
    int hidden_winding;
} params;

void main() {
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint index = group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
    bool valid = index < min(triangle_count, params.capacity) && RASTER_VARIANT != 4;
    RasterPass pass = RasterPass(params.size, params.frame_number, params.hidden_winding);
#if RASTER_SUBGROUP_WALK
    // Every invocation stays, so that the subgroup walks its large triangles together.
    vec4 clip[3] = valid ? triangles[index].clip : vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
    raster_draw_triangle_in_subgroup(pass, valid, clip[0], clip[1], clip[2], params.index_base + index);
#else
    if (valid) {
        raster_draw_triangle(pass, triangles[index].clip[0], triangles[index].clip[1],
                             triangles[index].clip[2], params.index_base + index);
    }
#endif
}
