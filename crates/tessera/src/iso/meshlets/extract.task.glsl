#version 460
// Mesh-shader path of the meshlet extraction, task stage (paper C §3.2.1): the region
// analysis of one occupied block, one mesh workgroup per subblock of its partition.
#extension GL_EXT_mesh_shader : require
#include "common/volume.glsl"
#include "common/exact.glsl"
#include "common/mc_tables.glsl"
#include "common/mc_cell.glsl"
#include "common/mc_vertex.glsl"
#include "common/mc_edges.glsl"
#include "iso/direct/block_list.glsl"
#include "iso/meshlets/params.glsl"
#include "iso/meshlets/buffers.glsl"
#include "iso/meshlets/payload.glsl"
#include "iso/meshlets/samples.glsl"
#include "iso/meshlets/subblock.glsl"

layout(local_size_x = MESHLET_WORKGROUP) in;
taskPayloadSharedEXT MeshletPayload payload;

#include "iso/meshlets/analysis.glsl"

void main() {
    uint listed = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (listed >= block_header.count) {
        EmitMeshTasksEXT(0u, 1u, 1u);  // the last row of a 2-D grid
    }
    meshlet_analyse(listed);
    EmitMeshTasksEXT(payload.subblock_count, 1u, 1u);
}
