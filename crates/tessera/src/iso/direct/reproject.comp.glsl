#version 460
// A second view of already extracted triangles (stereo): the first view's clip-space corners
// are taken to the second view's clip space (one matrix: the views share the grid), so the
// second eye costs rasterization and resolve but no extraction.
#include "raster/raster.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer FirstTriangles { RasterTriangle first_triangles[]; };
layout(binding = 1) readonly buffer FirstCounts { uint first_count; };
layout(binding = 2) writeonly buffer Triangles { RasterTriangle triangles[]; };
layout(binding = 3) buffer SecondCounts { uint second_count; };

layout(push_constant) uniform ReprojectParams {
    mat4 first_clip_to_second_clip;
    uvec4 capacity;  // x: triangles the second list holds
} params;

void main() {
    // Launched with the first view's raster dispatch (64-wide groups, rows past the limit).
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint t = group * 64u + gl_LocalInvocationIndex;
    uint count = min(first_count, params.capacity.x);
    if (t == 0u) {
        second_count = count;  // the second view's raster pass prepares its own dispatch
    }
    if (t >= count) {
        return;
    }
    for (uint j = 0u; j < 3u; ++j) {
        triangles[t].clip[j] = params.first_clip_to_second_clip * first_triangles[t].clip[j];
    }
}
