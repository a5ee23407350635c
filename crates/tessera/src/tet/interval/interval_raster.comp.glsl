#version 460
// Compute path of interval shading, first pass: one invocation per tet makes the mesh shader's
// proxies (tet/interval/proxy.glsl) and draws them itself or hands them to the tile pass
// (tet/interval/tet_draw.glsl).
#extension GL_EXT_shader_atomic_float : require
#if INTEGRAND == INTEGRAND_SDF
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif

layout(local_size_x = TETS_PER_WORKGROUP) in;

#include "tet/interval/pixel_passes.glsl"
#include "tet/interval/tet_draw.glsl"

void main() {
    // Workgroups spread over x and y past 65,535 (tessera_gpu::spread_groups).
    uint tet = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * uint(TETS_PER_WORKGROUP) + gl_LocalInvocationIndex;
    Proxy proxies[3];
    uint n = first_tet_proxies(tet, proxies);
    uvec2 first;
    uvec2 last;
    if (proxy_pixel_rect(proxies, n, first, last)) {
        draw_tet(tet, proxies, n, first, last);
    }
}
