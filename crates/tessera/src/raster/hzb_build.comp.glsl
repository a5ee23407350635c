#version 460
// Up to ilog2(HZB_TILE) + 2 levels of the max-depth pyramid (raster/hzb.glsl) in one
// dispatch: each workgroup takes a tile of 2 HZB_TILE × 2 HZB_TILE texels of the pass's first
// level, made from the level below (or from the rasterizer's frame for level 0), and folds it
// in shared memory into the HZB_TILE-square, ..., 2×2 and 1×1 texels above it. A texel past a
// level's edge holds NO_DEPTH, which no depth exceeds, so each texel is the max of its
// in-range sources: the same value as repeating the last row or column, as the per-level
// definition does. Max is exact, so the pyramid does not depend on how levels are grouped
// into passes.
#include "raster/raster.glsl"
#include "raster/hzb.glsl"

// HZB_TILE (a power of two) and RASTER_TILE come from raster::hzb and raster as defines.
layout(local_size_x = HZB_TILE, local_size_y = HZB_TILE) in;
layout(binding = 0) readonly buffer Frame { uvec2 depth_payload[]; };
layout(binding = 1) buffer Hzb { float hzb[]; };
// Per raster tile, the number of the last frame that drew into it (raster/mod.rs): pixels of
// tiles the frame did not draw into are empty, and are not read.
layout(binding = 2) readonly buffer TileFrames { uint tile_frames[]; };

layout(push_constant) uniform HzbBuildParams {
    uvec2 size;        // frame width and height in pixels
    uint first_level;  // the level this pass starts at (its sources are the level below)
    uint level_count;  // levels this pass builds, 1 ..= ilog2(HZB_TILE) + 2
    uint frame_number; // the number the frame's raster passes marked their tiles with
} params;

const float NO_DEPTH = -1.0;
const uint TILE = HZB_TILE;  // invocations per side; each folds a 2×2 of the first level
shared float s_depth[TILE][TILE];

float pixel_depth(uvec2 p) {
    if (tile_frames[raster_tile_index(p, params.size.x)] != params.frame_number) {
        return 1.0;
    }
    uvec2 value = depth_payload[p.y * params.size.x + p.x];
    return raster_is_empty(value) ? 1.0 : raster_depth(value);
}

// Texel `t` of the pass's first level from its in-range 2×2 sources, NO_DEPTH past the edge.
float first_level_texel(uvec2 t, uvec2 dims, uvec2 src_dims, uint src_offset) {
    if (any(greaterThanEqual(t, dims))) {
        return NO_DEPTH;
    }
    float far_depth = NO_DEPTH;
    for (uint c = 0u; c < 4u; ++c) {
        uvec2 s = 2u * t + uvec2(c & 1u, c >> 1);
        if (all(lessThan(s, src_dims))) {
            far_depth = max(far_depth, params.first_level == 0u
                ? pixel_depth(s)
                : hzb[src_offset + s.y * src_dims.x + s.x]);
        }
    }
    return far_depth;
}

// Texel `t` of the level that starts at `offset` with `dims` texels, if it lies inside.
void store(uint offset, uvec2 dims, uvec2 t, float far_depth) {
    if (all(lessThan(t, dims))) {
        hzb[offset + t.y * dims.x + t.x] = far_depth;
    }
}

void main() {
    uvec2 size = params.size;
    uint first = params.first_level;
    uvec2 local = gl_LocalInvocationID.xy;
    // Each level's size and start are found once (loops over the levels below) and then
    // stepped level by level, not recomputed per texel.
    uvec2 dims = hzb_level_dims(size, first);
    uint offset = hzb_level_offset(size, first);
    uvec2 src_dims = first == 0u ? size : hzb_level_dims(size, first - 1u);
    uint src_offset = first == 0u ? 0u : hzb_level_offset(size, first - 1u);

    // The first level: a 2×2 of texels per invocation, written out as they are.
    uvec2 corner = 2u * gl_GlobalInvocationID.xy;
    float far_depth = NO_DEPTH;
    for (uint c = 0u; c < 4u; ++c) {
        uvec2 t = corner + uvec2(c & 1u, c >> 1);
        float d = first_level_texel(t, dims, src_dims, src_offset);
        store(offset, dims, t, d);
        far_depth = max(far_depth, d);
    }
    // The levels above, halving the tile in shared memory.
    uint side = TILE;
    for (uint k = 1u; k < params.level_count; ++k) {
        offset += dims.x * dims.y;
        dims = (dims + 1u) / 2u;
        if (all(lessThan(local, uvec2(side)))) {
            store(offset, dims, gl_WorkGroupID.xy * side + local, far_depth);
            s_depth[local.y][local.x] = far_depth;
        }
        barrier();
        side /= 2u;
        if (all(lessThan(local, uvec2(side)))) {
            uvec2 s = 2u * local;
            far_depth = max(max(s_depth[s.y][s.x], s_depth[s.y][s.x + 1u]),
                            max(s_depth[s.y + 1u][s.x], s_depth[s.y + 1u][s.x + 1u]));
        }
        barrier();
    }
}
