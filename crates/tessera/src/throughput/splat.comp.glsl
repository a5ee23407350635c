#version 460
// The naive compute splat of the grid triangles: one invocation per triangle tests the pixel
// centres of its bounding box against the three edges and stores SPLAT_COVERED into each one
// inside. No depth, no ordering: it writes exactly the pixels rasterization would cover, which is
// all the comparison with grid.mesh.glsl needs.
#include "common/throughput.glsl"

layout(local_size_x = 64) in;
layout(binding = 0) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform TriangleParams {
    uvec2 size;      // target width, height
    uint triangles;  // total triangle count
} params;

const uint SPLAT_COVERED = 0xffffffffu;

// Twice the signed area of (a, b, p): which side of the line a->b the point p lies on.
float edge(vec2 a, vec2 b, vec2 p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

void main() {
    uint group = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
    uint t = group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
    if (t >= params.triangles) {
        return;
    }
    vec2 a, b, c;
    grid_triangle(t, params.size, a, b, c);
    // Orient the edge tests by the winding so both triangle kinds use the same inside test.
    float winding = sign(edge(a, b, c));
    ivec2 lo = max(ivec2(floor(min(a, min(b, c)))), ivec2(0));
    ivec2 hi = min(ivec2(ceil(max(a, max(b, c)))), ivec2(params.size));
    for (int y = lo.y; y < hi.y; ++y) {
        for (int x = lo.x; x < hi.x; ++x) {
            vec2 p = vec2(x, y) + 0.5;
            // No pixel centre lies on an edge of a grid triangle, so > versus >= never matters.
            vec3 e = vec3(edge(b, c, p), edge(c, a, p), edge(a, b, p)) * winding;
            if (all(greaterThan(e, vec3(0.0)))) {
                pixels[uint(y) * params.size.x + uint(x)] = SPLAT_COVERED;
            }
        }
    }
}
