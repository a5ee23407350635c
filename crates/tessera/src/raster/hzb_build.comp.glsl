#version 460
// One level of the max-depth pyramid (iso/direct/hzb.glsl): level 0 from the rasterizer's
// frame, every other level from the one below.
#include "raster/raster.glsl"
#include "raster/hzb.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) readonly buffer Frame { uvec2 depth_payload[]; };
layout(binding = 1) buffer Hzb { float hzb[]; };

layout(push_constant) uniform HzbParams {
    uvec4 size;  // x, y frame width and height; z the level to build
} params;

float pixel_depth(uvec2 p) {
    uvec2 value = depth_payload[p.y * params.size.x + p.x];
    return raster_is_empty(value) ? 1.0 : raster_depth(value);
}

void main() {
    uvec2 size = params.size.xy;
    uint level = params.size.z;
    uvec2 t = gl_GlobalInvocationID.xy;
    uvec2 dims = hzb_level_dims(size, level);
    if (any(greaterThanEqual(t, dims))) {
        return;
    }
    // The 2×2 sources, the last row or column standing in for one past the edge.
    uvec2 src_dims = level == 0u ? size : hzb_level_dims(size, level - 1u);
    uvec2 lo = 2u * t;
    uvec2 hi = min(lo + 1u, src_dims - 1u);
    float far_depth = 0.0;
    if (level == 0u) {
        far_depth = max(max(pixel_depth(lo), pixel_depth(uvec2(hi.x, lo.y))),
                        max(pixel_depth(uvec2(lo.x, hi.y)), pixel_depth(hi)));
    } else {
        uint src = hzb_level_offset(size, level - 1u);
        far_depth = max(max(hzb[src + lo.y * src_dims.x + lo.x], hzb[src + lo.y * src_dims.x + hi.x]),
                        max(hzb[src + hi.y * src_dims.x + lo.x], hzb[src + hi.y * src_dims.x + hi.x]));
    }
    hzb[hzb_level_offset(size, level) + t.y * dims.x + t.x] = far_depth;
}
