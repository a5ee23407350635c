#version 460
#extension GL_EXT_control_flow_attributes : require
// Level 0 of the min-max octree from a buffer of the samples (x fastest, packed as the volume
// holds them) rather than the 3-D texture. A workgroup takes 32 blocks along x of one block
// row; lane i takes block i and walks the block's rows of samples (y, z), one row in eight per
// invocation row. Along a row the 32 lanes read neighbouring stretches, so a warp's loads fall
// in a few cache lines and every sample is fetched from memory about once (the shared end
// samples of two blocks and the shared faces of block rows come from cache). A lane keeps its
// block's range in registers; the eight row walkers of a block meet once in shared memory.
// Samples are read as 32-bit words, so the buffer holds whole words.
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
// Rows of samples of a whole block ((BLOCK_Y + 1) × (BLOCK_Z + 1)), and how many each walker takes.
const uint ROWS_PER_WALKER = ((BLOCK_Y + 1u) * (BLOCK_Z + 1u) + WALKERS - 1u) / WALKERS;
// Words that a whole block's row of BLOCK_X + 1 samples fills; with more than one sample a
// word, the row's last sample is the first of the word after them.
const uint ROW_WORDS = (BLOCK_X + 1u) / SAMPLES_PER_WORD;
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

// (+inf, -inf): the range of no samples, which any merge replaces.
vec2 empty_range() {
    return vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
}

// The range of the block's rows when every row starts on a word (the volume's rows are whole
// words): each walker loads all its rows' words before it looks at any, so that its loads are
// in flight together (a row at a time, the walk over a 512³ uint8 volume took 1.8× as long as
// a compute copy of its bytes; loaded ahead, with integer samples compared as integers, 0.94×).
// A row past the block's last, or a word past the row's last, is read again in place of the
// one missing: a sample counted twice leaves a minimum and a maximum as they are.
vec2 aligned_rows_range(uvec3 lo, uvec3 hi, uint walker, uvec3 dims) {
    uint rows_y = hi.y - lo.y + 1u;
    uint rows = rows_y * (hi.z - lo.z + 1u);
    uint row_samples = hi.x - lo.x + 1u;
    // Whole words of the row; at the volume's last block along x the row ends on a word.
    uint last_word = row_samples / SAMPLES_PER_WORD - 1u;
    uint words[ROWS_PER_WALKER][ROW_WORDS];
#if SAMPLE_FLOAT == 0
    // The word holding the row's last sample where that is not in the whole words.
    uint tails[ROWS_PER_WALKER];
    uint tail = row_samples % SAMPLES_PER_WORD == 0u ? last_word : last_word + 1u;
#endif
    [[unroll]] for (uint i = 0u; i < ROWS_PER_WALKER; ++i) {
        uint r = min(walker + i * WALKERS, rows - 1u);
        uint y = lo.y + r % rows_y;
        uint z = lo.z + r / rows_y;
        uint first = ((z * dims.y + y) * dims.x + lo.x) / SAMPLES_PER_WORD;
        [[unroll]] for (uint j = 0u; j < ROW_WORDS; ++j) {
            words[i][j] = sample_words[first + min(j, last_word)];
        }
#if SAMPLE_FLOAT == 0
        tails[i] = sample_words[first + tail];
#endif
    }
#if SAMPLE_FLOAT
    vec2 range = empty_range();
    [[unroll]] for (uint i = 0u; i < ROWS_PER_WALKER; ++i) {
        [[unroll]] for (uint j = 0u; j < ROW_WORDS; ++j) {
            range = merge(range, vec2(uintBitsToFloat(words[i][j])));
        }
    }
#else
    // Integer samples compared as integers, converted once.
    uint lowest = 0xffffffffu;
    uint highest = 0u;
    [[unroll]] for (uint i = 0u; i < ROWS_PER_WALKER; ++i) {
        [[unroll]] for (uint j = 0u; j < ROW_WORDS; ++j) {
            [[unroll]] for (uint k = 0u; k < SAMPLES_PER_WORD; ++k) {
                uint v = bitfieldExtract(words[i][j], int(k * 8u * SAMPLE_BYTES), int(8u * SAMPLE_BYTES));
                lowest = min(lowest, v);
                highest = max(highest, v);
            }
        }
        // Only its first sample is the row's (or, at the last block, one of the whole words').
        uint v = bitfieldExtract(tails[i], 0, int(8u * SAMPLE_BYTES));
        lowest = min(lowest, v);
        highest = max(highest, v);
    }
    vec2 range = vec2(float(lowest), float(highest));
#endif
    return range;
}

// The range of the block's rows in any volume: rows may start within a word.
vec2 any_rows_range(uvec3 lo, uvec3 hi, uint walker, uvec3 dims) {
    vec2 range = empty_range();
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
    return range;
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
    vec2 range = empty_range();
    if (block.x < blocks.x) {
        // The same for every invocation of the dispatch.
        if (dims.x % SAMPLES_PER_WORD == 0u) {
            range = aligned_rows_range(lo, hi, walker, dims);
        } else {
            range = any_rows_range(lo, hi, walker, dims);
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
