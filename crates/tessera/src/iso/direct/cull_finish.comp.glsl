#version 460
// End of a culled compute-path frame, one invocation: the resolve listed the blocks that own a
// pixel for next frame's first pass (resolve.comp.glsl, SEEN_BLOCK_LIST); this sizes that
// list's dispatch and writes the frame's statistics straight into host-visible memory. A pass
// over every block's flag stood here before (0.043 ms at 1024³ on an H100), and four copies
// to the host after it took 0.011 ms of a 0.27-ms frame (docs/BENCHMARKS.md, runs 122–123).
#include "iso/direct/block_list.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 1) in;
// Next frame's pass-A list, one workgroup per block.
layout(binding = 0) buffer NextBlocks { BlockListHeader next_list; };
// [0] blocks occupied, [1] blocks listed for pass B (hzb_test.comp.glsl).
layout(binding = 1) readonly buffer Stats { uint stats[]; };
// This frame's pass-A list (its length: the blocks pass A drew).
layout(binding = 2) readonly buffer FirstBlocks { BlockListHeader first_list; };
// Each extraction's statistics (extract.comp.glsl): pass A's, pass B's.
layout(binding = 3) readonly buffer FirstExtraction { uint first_extraction[]; };
layout(binding = 4) readonly buffer NewExtraction { uint new_extraction[]; };
// The host's copy (ComputeCullStats): blocks occupied, listed for pass B, visible, the pass-A
// list's length, pass A's triangles, then pass B's three words.
layout(binding = 5) writeonly buffer HostStats { uint host_stats[]; };

void main() {
    uint visible = next_list.count;
    GROW_INDIRECT_ARGS3(next_list.args, visible, 1u);
    host_stats[0] = stats[0];
    host_stats[1] = stats[1];
    host_stats[2] = visible;
    host_stats[3] = first_list.count;
    host_stats[4] = first_extraction[0];
    for (uint i = 0u; i < 3u; ++i) {
        host_stats[5u + i] = new_extraction[i];
    }
}
