#version 460
// Level 0 of the min-max octree from a buffer of the samples (x fastest, packed as the volume
// holds them) rather than the 3-D texture. A workgroup takes 32 blocks along x of one block
// row; lane i takes block i and walks the block's rows of samples (y, z), eight rows at a
// time, one per invocation row. Along a row the 32 lanes read neighbouring stretches, so a
// warp's loads fall in a few cache lines and every sample is fetched from memory about once
// (the shared end samples of two blocks and the shared faces of block rows come from cache).
// A lane keeps its block's range in registers; the eight row walkers of a block meet once in
// shared memory. Samples are read as 32-bit words, so the buffer holds whole words.
// SAMPLE_BYTES (1, 2 or 4) and SAMPLE_FLOAT describe the samples.

layout(local_size_x = 32, local_size_y = 8) in;
layout(binding = 0) readonly buffer Samples { uint sample_words[]; };
layout(binding = 1) writeonly buffer Nodes { vec2 minmax_nodes[]; };

layout(push_constant) uniform BlockParams {
    uvec4 volume_dims;  // xyz samples per axis
    uvec4 block_dims;   // xyz blocks per axis
} params;

const uint SAMPLES_PER_WORD = 4u / SAMPLE_BYTES;
const uint WALKERS = 8u;
shared vec2 s_partial[WALKERS][32];

float sample_of_word(uint word, uint k) {
#if SAMPLE_FLOAT
    return uintBitsToFloat(word);
#else
    return float(bitfieldExtract(word, int(k * 8u * SAMPLE_BYTES), int(8u * SAMPLE_BYTES)));
#endif
}

vec2 merge(vec2 a, vec2 b) {
    return vec2(min(a.x, b.x), max(a.y, b.y));
}

void main() {
    uvec3 dims = params.volume_dims.xyz;
    uvec3 blocks = params.block_dims.xyz;
    uint lane = gl_LocalInvocationID.x;
    uint walker = gl_LocalInvocationID.y;
    uvec3 block = uvec3(gl_WorkGroupID.x * 32u + lane, gl_WorkGroupID.y, gl_WorkGroupID.z);
    const uvec3 BLOCK = uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    // The block's samples: its cells' corners, up to the next block's first sample.
    uvec3 lo = block * BLOCK;
    uvec3 hi = min(lo + BLOCK, dims - 1u);
    vec2 range = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
    if (block.x < blocks.x) {
        uint rows_y = hi.y - lo.y + 1u;
        uint rows = rows_y * (hi.z - lo.z + 1u);
        for (uint r = walker; r < rows; r += WALKERS) {
            uint y = lo.y + r % rows_y;
            uint z = lo.z + r / rows_y;
            uint first = (z * dims.y + y) * dims.x + lo.x;  // flat sample indices
            uint last = first + (hi.x - lo.x);
            for (uint w = first / SAMPLES_PER_WORD; w <= last / SAMPLES_PER_WORD; ++w) {
                uint word = sample_words[w];
                for (uint k = 0u; k < SAMPLES_PER_WORD; ++k) {
                    uint s = w * SAMPLES_PER_WORD + k;
                    if (s >= first && s <= last) {
                        range = merge(range, vec2(sample_of_word(word, k)));
                    }
                }
            }
        }
    }
    s_partial[walker][lane] = range;
    barrier();
    if (walker == 0u && block.x < blocks.x) {
        for (uint i = 1u; i < WALKERS; ++i) {
            range = merge(range, s_partial[i][lane]);
        }
        minmax_nodes[block.x + blocks.x * (block.y + blocks.y * block.z)] = range;
    }
}
