#version 460
// End of a culled compute-path frame, one invocation per block: the blocks that own a pixel
// (bit 0 of their flags, set by the resolve) become next frame's first-pass list, and their
// flags become "drawn first" (bit 1) for next frame's occlusion test. The workgroup that
// finishes last (a counter the others add to) writes the frame's statistics straight into
// host-visible memory: four copies to the host after this pass took 0.010 ms of a 0.27-ms
// frame on an H100 (docs/BENCHMARKS.md, run 122).
#include "raster/hzb.glsl"
#include "iso/direct/block_list.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 256) in;
layout(binding = 0) buffer BlockFlags { uint block_flags[]; };
// Next frame's pass-A list; its dispatch arguments (one workgroup per block) grow here.
layout(binding = 1) buffer NextBlocks { BlockListHeader next_list; uint next_blocks[]; };
// [0] blocks occupied, [1] blocks listed for pass B, [2] blocks visible (owning a pixel, counted
// here); coherent: the last workgroup reads what the others added.
layout(binding = 2) coherent buffer Stats { uint stats[]; };
// This frame's pass-A list (its length: the blocks pass A drew).
layout(binding = 3) readonly buffer FirstBlocks { BlockListHeader first_list; };
// Each extraction's statistics (extract.comp.glsl): pass A's, pass B's.
layout(binding = 4) readonly buffer FirstExtraction { uint first_extraction[]; };
layout(binding = 5) readonly buffer NewExtraction { uint new_extraction[]; };
// The host's copy (ComputeCullStats): stats[0..3], the pass-A list's length, pass A's
// triangles, then pass B's three words.
layout(binding = 6) writeonly buffer HostStats { uint host_stats[]; };
// Workgroups finished (zero between frames: the last one resets it).
layout(binding = 7) coherent buffer Progress { uint groups_done; };

layout(push_constant) uniform CompactParams {
    uint block_count;
} params;

shared uint group_seen;
shared uint group_base;

void main() {
    uint me = gl_LocalInvocationIndex;
    if (me == 0u) {
        group_seen = 0u;
    }
    barrier();
    uint b = FLAT_INVOCATION;
    bool seen = false;
    uint slot = 0u;
    if (b < params.block_count) {
        uint flags = block_flags[b];
        seen = (flags & 1u) != 0u;
        uint next = seen ? 2u : 0u;
        if (flags != next) {
            block_flags[b] = next;
        }
        if (seen) {
            slot = atomicAdd(group_seen, 1u);
        }
    }
    barrier();
    if (me == 0u) {
        if (group_seen > 0u) {
            group_base = atomicAdd(next_list.count, group_seen);
            GROW_INDIRECT_ARGS3(next_list.args, group_base + group_seen, 1u);
            atomicAdd(stats[2], group_seen);
        }
    }
    barrier();
    if (seen) {
        next_blocks[group_base + slot] = b;
    }
    if (me == 0u) {
        memoryBarrierBuffer();
        uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
        if (atomicAdd(groups_done, 1u) + 1u == groups) {
            memoryBarrierBuffer();
            for (uint i = 0u; i < 3u; ++i) {
                host_stats[i] = stats[i];
            }
            host_stats[3] = first_list.count;
            host_stats[4] = first_extraction[0];
            for (uint i = 0u; i < 3u; ++i) {
                host_stats[5u + i] = new_extraction[i];
            }
            groups_done = 0u;
        }
    }
}
