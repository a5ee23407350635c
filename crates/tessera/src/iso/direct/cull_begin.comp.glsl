#version 460
// Start of a culled compute-path frame (compute_cull_frame.rs): empties the counts and list
// headers its passes fill, the first `words[k]` words of binding k, in one dispatch. Small
// transfer commands cost a frame more than a dispatch's few stores (docs/BENCHMARKS.md,
// run 123): seven fills and updates stood here.
layout(local_size_x = CULL_BEGIN_WORDS) in;
layout(binding = 0) writeonly buffer FirstCounts { uint first_counts[]; };
layout(binding = 1) writeonly buffer NewCounts { uint new_counts[]; };
layout(binding = 2) writeonly buffer Stats { uint stats[]; };
layout(binding = 3) writeonly buffer FirstExtraction { uint first_extraction[]; };
layout(binding = 4) writeonly buffer NewExtraction { uint new_extraction[]; };
layout(binding = 5) writeonly buffer NewBlocks { uint new_blocks[]; };
layout(binding = 6) writeonly buffer NextBlocks { uint next_blocks[]; };

layout(push_constant) uniform CullBeginParams {
    uvec4 words_low;   // words of bindings 0-3
    uvec4 words_high;  // words of bindings 4-6, then 0
} params;

void main() {
    uint i = gl_LocalInvocationIndex;
    if (i < params.words_low.x) first_counts[i] = 0u;
    if (i < params.words_low.y) new_counts[i] = 0u;
    if (i < params.words_low.z) stats[i] = 0u;
    if (i < params.words_low.w) first_extraction[i] = 0u;
    if (i < params.words_high.x) new_extraction[i] = 0u;
    if (i < params.words_high.y) new_blocks[i] = 0u;
    if (i < params.words_high.z) next_blocks[i] = 0u;
}
