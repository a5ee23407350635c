#version 460
// Compute path of interval shading, first pass: one invocation per tet makes the mesh shader's
// proxies (tet/interval/proxy.glsl); its subgroup draws them together
// (tet/interval/subgroup_draw.glsl; each invocation its own where the device lacks the
// subgroup operations), or the tile pass does (tet/interval/tet_draw.glsl).
#extension GL_EXT_shader_atomic_float : require
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif
#if INTERVAL_SUBGROUP_DRAW
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif

layout(local_size_x = TETS_PER_WORKGROUP) in;

#include "tet/interval/pixel_passes.glsl"
#include "tet/interval/tet_draw.glsl"
#if INTERVAL_SUBGROUP_DRAW
#include "tet/interval/subgroup_draw.glsl"
#endif

void main() {
    // Workgroups spread over x and y past 65,535 (tessera_gpu::spread_groups).
    uint tet = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * uint(TETS_PER_WORKGROUP) + gl_LocalInvocationIndex;
    Proxy proxies[3];
    uint n = first_tet_proxies(tet, proxies);
    uvec2 first;
    uvec2 last;
    bool here = proxy_pixel_rect(proxies, n, first, last) && drawn_here(tet, first, last);
#if INTERVAL_SUBGROUP_DRAW
    // A tet the near plane cut (up to three proxies) is rare enough to be drawn alone; a small
    // one is drawn faster alone than by a subgroup stepping through its tets one at a time
    // (tet/interval/mod.rs, SUBGROUP_DRAW_ABOVE_PIXELS and SubgroupDraw).
    uvec2 extent = last - first + 1u;
    uint pixels = here ? extent.x * extent.y : 0u;
    uint limit = subgroup_draw_limit(here && n == 1u, pixels);
    bool grouped = here && n == 1u && pixels > limit;
    if (here && !grouped) {
        draw_proxies(tet, proxies, n, first, last);
    }
    draw_subgroup(grouped, tet, proxies[0], first, last);
#else
    if (here) {
        draw_proxies(tet, proxies, n, first, last);
    }
#endif
}
