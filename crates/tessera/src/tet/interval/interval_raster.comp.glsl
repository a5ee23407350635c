#version 460
// Compute path of interval shading: the same proxies as the mesh shader (tet/interval/proxy.glsl),
// rasterized in compute — one invocation per tet walks its proxies' pixels and adds each
// pixel's interval length × absorption with float atomics. For GPUs whose graphics units are
// few; large proxies (close views) make single invocations long, a tiled version is next.
#extension GL_EXT_shader_atomic_float : require

layout(local_size_x = 64) in;
layout(binding = 0) readonly buffer Vertices { vec4 vertices_world[]; };
layout(binding = 1) readonly buffer Tets { uvec4 tets[]; };
layout(binding = 2) readonly buffer Absorption { vec4 absorption[]; };
layout(binding = 3) buffer Stats { uint stats[]; };  // [0] tets clipped at the near plane
layout(binding = 4) buffer Optical { float optical[]; };  // rgba per pixel, row-major

#include "tet/interval/params.glsl"
#include "tet/interval/proxy.glsl"
#include "tet/interval/length.glsl"

float edge_at(vec2 a, vec2 b, vec2 p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Top-left rule on a counter-clockwise triangle (y down): a pixel centre on an edge belongs to
// exactly one of the two proxies sharing it.
bool owns(float w, vec2 a, vec2 b) {
    vec2 d = b - a;
    return w > 0.0 || (w == 0.0 && ((d.y == 0.0 && d.x < 0.0) || d.y > 0.0));
}

void splat(vec2 ndc0, vec2 ndc1, vec2 ndc2, vec2 d0, vec2 d1, vec2 d2, vec3 colour) {
    uvec2 size = params.counts.yz;
    vec2 half_size = vec2(size) * 0.5;
    vec2 s0 = (ndc0 + 1.0) * half_size;
    vec2 s1 = (ndc1 + 1.0) * half_size;
    vec2 s2 = (ndc2 + 1.0) * half_size;
    float area = edge_at(s0, s1, s2);
    if (area == 0.0) {
        return;
    }
    if (area < 0.0) {
        vec2 ts = s1; s1 = s2; s2 = ts;
        vec2 td = d1; d1 = d2; d2 = td;
        area = -area;
    }
    vec2 lo = clamp(floor(min(s0, min(s1, s2))), vec2(0.0), vec2(size) - 1.0);
    vec2 hi = clamp(ceil(max(s0, max(s1, s2))), vec2(0.0), vec2(size) - 1.0);
    for (uint y = uint(lo.y); y <= uint(hi.y); ++y) {
        for (uint x = uint(lo.x); x <= uint(hi.x); ++x) {
            vec2 p = vec2(x, y) + 0.5;
            float w0 = edge_at(s1, s2, p);
            float w1 = edge_at(s2, s0, p);
            float w2 = edge_at(s0, s1, p);
            if (!(owns(w0, s1, s2) && owns(w1, s2, s0) && owns(w2, s0, s1))) {
                continue;
            }
            vec2 depths = (w0 * d0 + w1 * d1 + w2 * d2) / area;
            float len = interval_length(depths, p / half_size - 1.0);
            uint i = (y * size.x + x) * 4u;
            atomicAdd(optical[i + 0u], len * colour.r);
            atomicAdd(optical[i + 1u], len * colour.g);
            atomicAdd(optical[i + 2u], len * colour.b);
        }
    }
}

void main() {
    // Workgroups spread over x and y past 65,535 (tessera_gpu::spread_groups).
    uint tet = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
    if (tet >= params.counts.x) {
        return;
    }
    Proxy proxies[3];
    bool clipped;
    uint n = tet_proxies(tet, proxies, clipped);
    if (clipped) {
        atomicAdd(stats[0], 1u);
    }
    vec3 colour = absorption[tet].xyz;
    for (uint k = 0u; k < n; ++k) {
        uint s = proxies[k].silhouette;
        for (uint j = 0u; j < s; ++j) {
            uint a = j;
            uint b = (j + 1u) % s;
            splat(proxies[k].p[a], proxies[k].p[b], proxies[k].p[s],
                  proxies[k].depths[a], proxies[k].depths[b], proxies[k].depths[s], colour);
        }
    }
}
