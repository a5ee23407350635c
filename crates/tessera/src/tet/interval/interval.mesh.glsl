#version 460
// Interval shading (paper A, §2): each tetrahedron becomes 3 (case 1) or 4 (case 2) screen-space
// proxy triangles at depth 0 whose vertices carry the inverse view depth of the tet's front and
// back faces, so the rasterizer hands every fragment its [front, back] interval. A tet crossing
// the near plane is clipped first (§2.3): one vertex in front leaves a tet, two or three leave a
// prism cut into 3 tets. One input tet per invocation, GROUP (a define: 1 to 16) per workgroup;
// 3 proxies each fit the output limits at 16 (16 × 15 vertices, 16 × 12 triangles).
#extension GL_EXT_mesh_shader : require

layout(local_size_x = GROUP) in;
layout(triangles, max_vertices = 15 * GROUP, max_primitives = 12 * GROUP) out;

#include "tet/interval/buffers.glsl"
#include "tet/interval/params.glsl"

layout(location = 0) out vec4 interval_attrs[];  // 1/z and s/z of front and back face (view space)
layout(location = 1) flat out uint tet_id[];

shared uint vertex_offsets[GROUP + 1u];
shared uint primitive_offsets[GROUP + 1u];

#include "tet/interval/proxy.glsl"

void main() {
    uint me = gl_LocalInvocationIndex;
    // Workgroups spread over x and y past 65,535 (tessera_gpu::spread_groups).
    uint tet = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * GROUP + me;
    Proxy proxies[3];
    uint proxy_count = first_tet_proxies(tet, proxies);
    uint vertex_count = 0u;
    uint primitive_count = 0u;
    for (uint k = 0u; k < proxy_count; ++k) {
        uint s = proxies[k].silhouette;
        vertex_count += s == 0u ? 0u : s + 1u;
        primitive_count += s;
    }
    vertex_offsets[me + 1u] = vertex_count;
    primitive_offsets[me + 1u] = primitive_count;
    barrier();
    if (me == 0u) {
        vertex_offsets[0] = 0u;
        primitive_offsets[0] = 0u;
        for (uint i = 1u; i <= GROUP; ++i) {
            vertex_offsets[i] += vertex_offsets[i - 1u];
            primitive_offsets[i] += primitive_offsets[i - 1u];
        }
    }
    barrier();
    SetMeshOutputsEXT(vertex_offsets[GROUP], primitive_offsets[GROUP]);
    uint v = vertex_offsets[me];
    uint q = primitive_offsets[me];
    for (uint k = 0u; k < proxy_count; ++k) {
        uint s = proxies[k].silhouette;
        if (s == 0u) {
            continue;
        }
        for (uint j = 0u; j <= s; ++j) {
            gl_MeshVerticesEXT[v + j].gl_Position = vec4(proxies[k].p[j], 0.0, 1.0);
            interval_attrs[v + j] = proxies[k].attrs[j];
            tet_id[v + j] = tet;
        }
        for (uint j = 0u; j < s; ++j) {
            gl_PrimitiveTriangleIndicesEXT[q + j] = uvec3(v + j, v + (j + 1u) % s, v + s);
        }
        v += s + 1u;
        q += s;
    }
}
