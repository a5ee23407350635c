// Max-depth pyramid (HZB) of a width×height frame, all levels in one float buffer: level 0 has
// ceil(width / 2) × ceil(height / 2) texels, each the largest depth of its 2×2 pixels (an empty
// pixel counts as 1.0); level k + 1 is the 2×2 max of level k, rounding up, down to 1×1. Texel t
// of level k covers pixels [t << (k + 1), (t + 1) << (k + 1)). Levels follow each other
// row-major, level 0 first (host side: raster::hzb). Built from the shared compute rasterizer's
// frame by hzb_build.comp.glsl; occlusion tests read it through hzb_test.glsl.

#ifndef RASTER_HZB_GLSL
#define RASTER_HZB_GLSL

uvec2 hzb_level_dims(uvec2 size, uint level) {
    uvec2 d = (size + 1u) / 2u;
    for (uint k = 0u; k < level; ++k) {
        d = (d + 1u) / 2u;
    }
    return d;
}

// Levels of the pyramid of a frame of `size` pixels.
uint hzb_level_count(uvec2 size) {
    uint levels = 1u;
    for (uvec2 d = (size + 1u) / 2u; any(greaterThan(d, uvec2(1u))); d = (d + 1u) / 2u) {
        levels += 1u;
    }
    return levels;
}

uint hzb_level_offset(uvec2 size, uint level) {
    uint offset = 0u;
    uvec2 d = (size + 1u) / 2u;
    for (uint k = 0u; k < level; ++k) {
        offset += d.x * d.y;
        d = (d + 1u) / 2u;
    }
    return offset;
}

// The linear index of this invocation in a 1-D workload dispatched as a 2-D grid of
// workgroups (rows of at most the device's limit). A macro: it reads gl_WorkGroupSize, which
// must be declared first.
#define FLAT_INVOCATION \
    ((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationIndex)

#endif
