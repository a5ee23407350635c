#version 460
// Small grid triangles emitted by mesh shaders, no vertex buffers: each workgroup emits
// MESH_TRIANGLES triangles with their own three vertices (no sharing, as independent small
// triangles would have). Each invocation builds both triangles of one cell.
#extension GL_EXT_mesh_shader : require
#include "common/throughput.glsl"

const uint CELLS_PER_GROUP = MESH_TRIANGLES / 2u;
layout(local_size_x = CELLS_PER_GROUP) in;
layout(triangles, max_vertices = 3 * MESH_TRIANGLES, max_primitives = MESH_TRIANGLES) out;

layout(push_constant) uniform TriangleParams {
    uvec2 size;      // target width, height
    uint triangles;  // total triangle count
} params;

void main() {
    // Groups come as a 2-D grid so that counts past the per-axis limit still fit.
    uint group = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
    uint first = group * MESH_TRIANGLES;
    uint count = first < params.triangles ? min(MESH_TRIANGLES, params.triangles - first) : 0u;
    SetMeshOutputsEXT(count * 3u, count);
    vec2 to_ndc = 2.0 / vec2(params.size);
    for (uint k = 0u; k < 2u; ++k) {
        uint local = gl_LocalInvocationIndex * 2u + k;
        if (local >= count) {
            break;
        }
        vec2 corners[3];
        grid_triangle(first + local, params.size, corners[0], corners[1], corners[2]);
        for (uint v = 0u; v < 3u; ++v) {
            gl_MeshVerticesEXT[local * 3u + v].gl_Position =
                vec4(corners[v] * to_ndc - 1.0, 0.0, 1.0);
        }
        gl_PrimitiveTriangleIndicesEXT[local] = uvec3(local * 3u) + uvec3(0u, 1u, 2u);
    }
}
