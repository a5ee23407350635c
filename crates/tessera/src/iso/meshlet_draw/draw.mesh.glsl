#version 460
// One meshlet: its vertices projected, with the world-space attributes the fragment stage
// shades, and its triangles from the 8-bit local indices.
#extension GL_EXT_mesh_shader : require
#include "common/grid_world.glsl"
#include "iso/meshlet_draw/params.glsl"
#include "iso/meshlet_draw/buffers.glsl"
#include "iso/meshlet_draw/payload.glsl"
#include "iso/meshlet_draw/corner.glsl"

layout(local_size_x = 32) in;
layout(triangles, max_vertices = MESHLET_MAX_VERTICES, max_primitives = MESHLET_MAX_TRIANGLES) out;
layout(location = 0) out vec3 normal_world[];
layout(location = 1) out vec3 position_world[];

void main() {
    Meshlet m = meshlets[payload.meshlet_ids[gl_WorkGroupID.x]];
    uint vertex_count = meshlet_vertex_count(m);
    uint triangle_count = meshlet_triangle_count(m);
    SetMeshOutputsEXT(vertex_count, triangle_count);
    uint me = gl_LocalInvocationIndex;
    for (uint v = me; v < vertex_count; v += 32u) {
        SurfaceCorner c = surface_corner(meshlet_position(m.vertex_offset + v),
                                         meshlet_normal(m.vertex_offset + v));
        gl_MeshVerticesEXT[v].gl_Position = c.clip;
        normal_world[v] = c.normal_world;
        position_world[v] = c.position_world;
    }
    for (uint t = me; t < triangle_count; t += 32u) {
        uint first = 3u * (m.triangle_offset + t);
        gl_PrimitiveTriangleIndicesEXT[t] = uvec3(meshlet_local_index(first),
                                                  meshlet_local_index(first + 1u),
                                                  meshlet_local_index(first + 2u));
    }
    if (me == 0u) {
        atomicAdd(triangles_drawn, triangle_count);
    }
}
