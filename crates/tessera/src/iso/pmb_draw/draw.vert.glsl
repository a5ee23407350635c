#version 460
// One vertex of the PMB mesh: the indexed draw of its block already added the block's first
// vertex to the local index, so the vertex index addresses the shared arrays directly.
#include "common/grid_world.glsl"
#include "iso/meshlet_draw/params.glsl"
#include "iso/meshlet_draw/corner.glsl"

layout(binding = 0) readonly buffer Positions { float positions[]; };
layout(binding = 1) readonly buffer Normals { float normals[]; };
layout(location = 0) out vec3 normal_world;
layout(location = 1) out vec3 position_world;

void main() {
    uint v = 3u * uint(gl_VertexIndex);
    SurfaceCorner c = surface_corner(vec3(positions[v], positions[v + 1u], positions[v + 2u]),
                                     vec3(normals[v], normals[v + 1u], normals[v + 2u]));
    gl_Position = c.clip;
    normal_world = c.normal_world;
    position_world = c.position_world;
}
