#version 460
// Mesh-shader path of the meshlet extraction, mesh stage (paper C §3.2.2): the meshlet of one
// subblock into the output buffers. The pipeline produces buffers, not pixels: nothing is
// emitted for the rasterizer.
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
layout(triangles, max_vertices = 3, max_primitives = 1) out;
taskPayloadSharedEXT MeshletPayload payload;

#include "iso/meshlets/extraction.glsl"

void main() {
    SetMeshOutputsEXT(0u, 0u);
    meshlet_extract(gl_WorkGroupID.x, false);
}
