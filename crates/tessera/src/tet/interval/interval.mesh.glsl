#version 460
// Interval shading (paper A, §2): each tetrahedron becomes 3 (case 1) or 4 (case 2) screen-space
// proxy triangles at depth 0 whose vertices carry the inverse view depth of the tet's front and
// back faces, so the rasterizer hands every fragment its [front, back] interval. One tet per
// invocation, 32 per workgroup. Tets reaching the near plane are not clipped yet: they are
// skipped and counted.
#extension GL_EXT_mesh_shader : require

layout(local_size_x = 32) in;
layout(triangles, max_vertices = 160, max_primitives = 128) out;

layout(binding = 0) readonly buffer Vertices { vec4 vertices_world[]; };
layout(binding = 1) readonly buffer Tets { uvec4 tets[]; };
layout(binding = 2) readonly buffer Absorption { vec4 absorption[]; };
layout(binding = 3) buffer Stats { uint stats[]; };  // [0] tets skipped at the near plane

#include "tet/interval/params.glsl"

layout(location = 0) out vec2 inverse_depths[];       // 1/z of front and back face (view space)
layout(location = 1) flat out vec3 tet_absorption[];

shared uint vertex_offsets[33];
shared uint primitive_offsets[33];

// Twice the signed area of (a, b, c): the edge function.
float edge(vec2 a, vec2 b, vec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool inside(vec2 p, vec2 a, vec2 b, vec2 c) {
    float w0 = edge(b, c, p);
    float w1 = edge(c, a, p);
    float w2 = edge(a, b, p);
    return (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) || (w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0);
}

// Whether segments p-q and r-s cross; t and s_out are the crossing's weights along each.
bool crossing(vec2 p, vec2 q, vec2 r, vec2 s, out float t, out float u) {
    vec2 d1 = q - p;
    vec2 d2 = s - r;
    float denom = d1.x * d2.y - d1.y * d2.x;
    t = 0.0;
    u = 0.0;
    if (abs(denom) < 1e-20) {
        return false;
    }
    vec2 w = r - p;
    t = (w.x * d2.y - w.y * d2.x) / denom;
    u = (w.x * d1.y - w.y * d1.x) / denom;
    return t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0;
}

void main() {
    uint me = gl_LocalInvocationIndex;
    uint tet = gl_WorkGroupID.x * 32u + me;
    vec2 p[4];
    float inv_z[4];
    uint kind = 0u;  // 0 nothing, 1 triangle silhouette, 2 quad silhouette
    uint order[4] = uint[4](0u, 1u, 2u, 3u);
    float t = 0.0;
    float s = 0.0;
    vec3 lambda = vec3(0.0);
    if (tet < params.counts.x) {
        uvec4 ids = tets[tet];
        bool near = false;
        for (int i = 0; i < 4; ++i) {
            vec4 clip = params.world_to_clip * vec4(vertices_world[ids[i]].xyz, 1.0);
            near = near || clip.w <= params.view.w;
            p[i] = clip.xy / clip.w;
            inv_z[i] = 1.0 / clip.w;
        }
        if (near) {
            atomicAdd(stats[0], 1u);
        } else {
            kind = 2u;
            for (uint d = 0u; d < 4u && kind == 2u; ++d) {
                uint a = (d + 1u) & 3u, b = (d + 2u) & 3u, c = (d + 3u) & 3u;
                if (inside(p[d], p[a], p[b], p[c])) {
                    kind = 1u;
                    order = uint[4](a, b, c, d);
                    float area = edge(p[a], p[b], p[c]);
                    lambda = abs(area) > 1e-20
                        ? vec3(edge(p[b], p[c], p[d]), edge(p[c], p[a], p[d]), edge(p[a], p[b], p[d])) / area
                        : vec3(1.0, 0.0, 0.0);
                }
            }
            if (kind == 2u) {
                // The quad's diagonals are the pair of opposite edges that cross on screen.
                if (crossing(p[0], p[2], p[1], p[3], t, s)) {
                    order = uint[4](0u, 1u, 2u, 3u);
                } else if (crossing(p[0], p[1], p[2], p[3], t, s)) {
                    order = uint[4](0u, 2u, 1u, 3u);
                } else if (crossing(p[0], p[3], p[1], p[2], t, s)) {
                    order = uint[4](0u, 1u, 3u, 2u);
                } else {
                    kind = 0u;  // degenerate on screen: covers no pixel
                }
            }
        }
    }
    uint vertex_count = kind == 1u ? 4u : (kind == 2u ? 5u : 0u);
    uint primitive_count = kind == 1u ? 3u : (kind == 2u ? 4u : 0u);
    vertex_offsets[me + 1u] = vertex_count;
    primitive_offsets[me + 1u] = primitive_count;
    barrier();
    if (me == 0u) {
        vertex_offsets[0] = 0u;
        primitive_offsets[0] = 0u;
        for (uint i = 1u; i <= 32u; ++i) {
            vertex_offsets[i] += vertex_offsets[i - 1u];
            primitive_offsets[i] += primitive_offsets[i - 1u];
        }
    }
    barrier();
    SetMeshOutputsEXT(vertex_offsets[32], primitive_offsets[32]);
    if (kind == 0u) {
        return;
    }
    uint v0 = vertex_offsets[me];
    uint q0 = primitive_offsets[me];
    vec3 colour = absorption[tet].xyz;
    uint silhouette = kind == 1u ? 3u : 4u;
    for (uint j = 0u; j < silhouette; ++j) {
        uint i = order[j];
        gl_MeshVerticesEXT[v0 + j].gl_Position = vec4(p[i], 0.0, 1.0);
        inverse_depths[v0 + j] = vec2(inv_z[i]);
        tet_absorption[v0 + j] = colour;
    }
    vec2 centre;
    vec2 centre_depths;
    if (kind == 1u) {
        uint a = order[0], b = order[1], c = order[2], d = order[3];
        centre = p[d];
        // The inner vertex seen on the opposite face: 1/z is affine in screen space on a plane.
        centre_depths = vec2(inv_z[d], dot(lambda, vec3(inv_z[a], inv_z[b], inv_z[c])));
    } else {
        uint a = order[0], b = order[1], c = order[2], d = order[3];
        centre = p[a] + (p[c] - p[a]) * t;
        centre_depths = vec2(inv_z[a] + (inv_z[c] - inv_z[a]) * t, inv_z[b] + (inv_z[d] - inv_z[b]) * s);
    }
    uint centre_index = v0 + silhouette;
    gl_MeshVerticesEXT[centre_index].gl_Position = vec4(centre, 0.0, 1.0);
    inverse_depths[centre_index] = centre_depths;
    tet_absorption[centre_index] = colour;
    for (uint j = 0u; j < silhouette; ++j) {
        gl_PrimitiveTriangleIndicesEXT[q0 + j] = uvec3(v0 + j, v0 + (j + 1u) % silhouette, centre_index);
    }
}
