#version 460
// Mesh-shader path of the meshlet extraction, task stage (paper C §3.2.1): the region
// analysis of one occupied block, one mesh workgroup per subblock of its partition.
#extension GL_EXT_mesh_shader : require
#include "common/volume.glsl"
#include "common/ablation.glsl"
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
#include "iso/meshlets/scan.glsl"

layout(local_size_x = MESHLET_WORKGROUP) in;
taskPayloadSharedEXT MeshletPayload payload;

#include "iso/meshlets/analysis.glsl"

void main() {
    uint listed = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    // Past the list only in the last row of a 2-D grid; the same for the whole workgroup, so
    // the analysis's barriers stay in uniform control flow. One EmitMeshTasksEXT, at the end:
    // with an early one for the rows' tail, NVIDIA's driver (580) extracted some blocks twice
    // once the list passed one row (docs/BENCHMARKS.md, run 44).
    bool listed_block = listed < block_header.count;
    if (listed_block) {
        meshlet_analyse(listed);
    }
#if EXTRACTION_ABLATION == ABLATION_ANALYSIS_ONLY
    listed_block = false;
#endif
    EmitMeshTasksEXT(listed_block ? payload.subblock_count : 0u, 1u, 1u);
}
