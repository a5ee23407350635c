#version 460
// Compute path of the meshlet extraction: the task stage's region analysis and the mesh
// stage's extraction of each subblock, one after the other, in one workgroup per occupied
// block; the payload lives in shared memory, and the extraction reads the analysis's list of
// occupied cells and their table rows from shared memory too.
//
// Two passes, from this one source: MESHLET_SPLIT_PASS 0 takes every occupied block, extracts
// those that fit one meshlet whole (most) and lists the others in `split_blocks`; pass 1 takes
// the listed blocks, partitions them and extracts their subblocks. The first pass then holds
// no code for partitions and subblocks, so it needs far fewer registers, and more of its
// workgroups fit on a multiprocessor at once.
#if MESHLET_SUBGROUP_SCAN
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
#define MESHLET_ANALYSIS_IN_WORKGROUP
#if !MESHLET_SPLIT_PASS
#define MESHLET_FITTING_BLOCKS_ONLY
#endif
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
shared MeshletPayload payload;
// Entries of the occupied-block list whose block does not fit one meshlet whole.
layout(binding = 8) coherent buffer SplitBlocks { BlockListHeader split_header; uint split_blocks[]; };

#include "iso/meshlets/analysis.glsl"
#include "iso/meshlets/extraction.glsl"

void main() {
    uint entry = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
#if MESHLET_SPLIT_PASS
    if (entry >= split_header.count) {
        return;  // the last row of a 2-D grid; uniform across the workgroup
    }
    uint listed = split_blocks[entry];
#else
    if (entry >= block_header.count) {
        return;
    }
    uint listed = entry;
#endif
    // The analysis's barriers publish the cleared outputs to the first extraction.
    meshlet_clear_outputs();
    meshlet_analyse(listed);
#if EXTRACTION_ABLATION != ABLATION_ANALYSIS_ONLY
    for (uint s = 0u; s < payload.subblock_count; ++s) {
        if (s > 0u) {
            barrier();  // the previous subblock's shared outputs are read out
        }
        meshlet_extract(s, true);
    }
#endif
}
