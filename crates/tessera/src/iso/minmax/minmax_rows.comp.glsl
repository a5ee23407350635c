#version 460
// Every level of the min-max octree in one dispatch, from a buffer of the samples (x
// fastest, packed as the volume holds them) rather than the 3-D texture.
//
// Level 0: a workgroup takes 32 blocks along x of one block row and reads their rows of
// samples (y, z) a whole row of 32 blocks at a time: invocation i reads word i of the row,
// so a warp's load is one run of 128 bytes and every sample is fetched from memory about
// once (the end sample each block shares with the next, and the face rows block rows
// share, come from cache). Each invocation merges its words' samples over its rows; the
// eight invocations of a block (its words in a row × the rows read at once) meet once in
// shared memory. An earlier walk, a lane per block reading its block's row stretches, made
// six cache-line requests per row of 32 uint8 blocks where this makes two.
//
// Levels above: each level-3 node (8×8×8 blocks) counts the workgroups that have written
// their blocks of it; the workgroup that completes the count builds levels 1–3 of that node
// (64 invocations, as `minmax_levels.comp.glsl` does a node), and so up, three levels at a
// time, each level-3k node counted by the level-3(k-1) nodes below it, until the root. The
// last arrival resets its counter, so the counters are zero for the next build. One
// dispatch replaces a level pass and a barrier per three levels. Samples are read as 32-bit
// words, so the buffer holds whole words; SAMPLE_BYTES (1, 2 or 4) and SAMPLE_FLOAT describe
// the samples. `level_count` 1 builds level 0 alone.
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x = 256) in;
layout(binding = 0) readonly buffer Samples { uint sample_words[]; };
// Coherent: a workgroup reads the nodes other workgroups wrote in this dispatch.
layout(binding = 1) coherent buffer Nodes { vec2 minmax_nodes[]; };
// Per level: nodes per axis, and in w the index of its first node.
layout(binding = 2) readonly buffer Levels { uvec4 levels[]; };
// One arrival counter per node of levels 3, 6, 9, … (level 3 first), zero between builds.
layout(binding = 3) coherent buffer Arrivals { uint arrivals[]; };

layout(push_constant) uniform RowsParams {
    uvec4 volume_dims;  // xyz samples per axis
    uvec4 block_dims;   // xyz blocks per axis (level 0's nodes)
    uint level_count;
} params;

const uint SAMPLES_PER_WORD = 4u / SAMPLE_BYTES;
const uint BLOCKS_PER_GROUP = 32u;
const uint WORDS_PER_BLOCK = BLOCK_X / SAMPLES_PER_WORD;
const uint ROW_WORDS = BLOCKS_PER_GROUP * WORDS_PER_BLOCK;
const uint ROWS_AT_ONCE = 256u / ROW_WORDS;
// Invocations that share a block (8 for every sample size).
const uint BLOCK_READERS = WORDS_PER_BLOCK * ROWS_AT_ONCE;
const uint BLOCK_ROWS = (BLOCK_Y + 1u) * (BLOCK_Z + 1u);
const uint ROW_STEPS = (BLOCK_ROWS + ROWS_AT_ONCE - 1u) / ROWS_AT_ONCE;
const uint ROW_BATCH = 8u;
// Nodes of the level below a level-3k node, per axis.
const uint FAN_OUT = 8u;
// The level-3 nodes one workgroup's 32 blocks fall in, and so the subtree builders.
const uint SUBTREES = BLOCKS_PER_GROUP / FAN_OUT;

// Level 0's partial ranges, then each subtree builder's 64 ranges.
shared vec2 s_ranges[256];
shared bool s_builds[SUBTREES];

const vec2 EMPTY_RANGE = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));

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

uvec3 corner(uint c) {
    return uvec3(c & 1u, (c >> 1) & 1u, c >> 2);
}

// Nodes per axis of `level`, also above the root (one).
uvec3 dims_of_level(uint level) {
    uvec3 size = uvec3(1u << level);
    return (params.block_dims.xyz + size - 1u) / size;
}

uint node_index(uint level, uvec3 p) {
    uvec4 l = levels[level];
    return l.w + p.x + l.x * (p.y + l.y * p.z);
}

// The counter of node `p` of level 3k.
uint arrival_slot(uint level, uvec3 p) {
    uint first = 0u;
    for (uint l = 3u; l < level; l += 3u) {
        uvec3 d = dims_of_level(l);
        first += d.x * d.y * d.z;
    }
    uvec3 d = dims_of_level(level);
    return first + p.x + d.x * (p.y + d.y * p.z);
}

// Arrivals node `p` of level 3k waits for: one per level-3(k-1) node under it; at level 3,
// one per block row of it (a workgroup covers the node's whole x extent).
uint arrivals_expected(uint level, uvec3 p) {
    uvec3 below = min(uvec3(FAN_OUT), dims_of_level(level - 3u) - p * FAN_OUT);
    return level == 3u ? below.y * below.z : below.x * below.y * below.z;
}

// Counts one arrival at node `p` of level 3k; true for the one that completes it.
bool arrive(uint level, uvec3 p) {
    uint slot = arrival_slot(level, p);
    bool last = atomicAdd(arrivals[slot], 1u) + 1u == arrivals_expected(level, p);
    if (last) {
        arrivals[slot] = 0u;
    }
    return last;
}

// Writes node `p` of `level` where the octree has that level and node.
void store(uint level, uvec3 p, vec2 range) {
    if (level < params.level_count && all(lessThan(p, levels[level].xyz))) {
        minmax_nodes[node_index(level, p)] = range;
    }
}

// The range of the samples of this invocation's word column over its rows, merged over the
// block's readers into invocation `block` of the workgroup.
vec2 block_range(uint invocation) {
    uvec3 dims = params.volume_dims.xyz;
    uint column = invocation % ROW_WORDS;
    uint first_row = invocation / ROW_WORDS;
    // Samples x0 .. x0 + SAMPLES_PER_WORD - 1 of each row, and x0 + SAMPLES_PER_WORD where
    // that is the block's last sample (shared with the next block).
    uint x0 = gl_WorkGroupID.x * BLOCKS_PER_GROUP * BLOCK_X + column * SAMPLES_PER_WORD;
    bool block_end = column % WORDS_PER_BLOCK == WORDS_PER_BLOCK - 1u;
    uint x_end = min(x0 + SAMPLES_PER_WORD - uint(!block_end), dims.x - 1u);
    uint y0 = gl_WorkGroupID.y * BLOCK_Y;
    uint z0 = gl_WorkGroupID.z * BLOCK_Z;
    uint rows_y = min(BLOCK_Y, dims.y - 1u - y0) + 1u;
    uint rows = rows_y * (min(BLOCK_Z, dims.z - 1u - z0) + 1u);
    uint span = x_end - x0;  // samples after the first (SAMPLES_PER_WORD or one fewer)
    bool inside = x0 <= x_end;
    vec2 range = EMPTY_RANGE;
    // Rows in batches whose loads are all issued before any is merged: one load in flight
    // per invocation would leave the memory system idle.
    for (uint batch = 0u; batch < ROW_STEPS; batch += ROW_BATCH) {
        uint firsts[ROW_BATCH];
        uint words[ROW_BATCH];
        uint nexts[ROW_BATCH];
        [[unroll]] for (uint b = 0u; b < ROW_BATCH; ++b) {
            uint r = first_row + (batch + b) * ROWS_AT_ONCE;
            bool row = inside && r < rows;
            uint y = y0 + r % rows_y;
            uint z = z0 + r / rows_y;
            uint first = (z * dims.y + y) * dims.x + x0;  // flat sample index
            uint word = first / SAMPLES_PER_WORD;
            // A row that starts mid-word, or the block's end sample, reaches into the next
            // word.
            bool spills = (first + span) / SAMPLES_PER_WORD != word;
            firsts[b] = row ? first : ~0u;
            words[b] = row ? sample_words[word] : 0u;
            nexts[b] = row && spills ? sample_words[word + 1u] : 0u;
        }
        [[unroll]] for (uint b = 0u; b < ROW_BATCH; ++b) {
            if (firsts[b] != ~0u) {
                uint offset = firsts[b] % SAMPLES_PER_WORD;
                [[unroll]] for (uint k = 0u; k <= SAMPLES_PER_WORD; ++k) {
                    uint at = offset + k;
                    uint word = at < SAMPLES_PER_WORD ? words[b] : nexts[b];
                    if (k <= span) {
                        range = merge(range, vec2(sample_of_word(word, at % SAMPLES_PER_WORD)));
                    }
                }
            }
        }
    }
    s_ranges[invocation] = range;
    barrier();
    uint block = invocation;
    range = EMPTY_RANGE;
    if (block < BLOCKS_PER_GROUP) {
        for (uint i = 0u; i < BLOCK_READERS; ++i) {
            uint reader = (i / WORDS_PER_BLOCK) * ROW_WORDS + block * WORDS_PER_BLOCK
                + i % WORDS_PER_BLOCK;
            range = merge(range, s_ranges[reader]);
        }
    }
    return range;
}

// Builds levels `child + 1 ..= child + 3` of node `top` (level child + 3) from level `child`,
// by the 64 invocations `me` of subtree builder `builder`, where `build`. Every invocation
// of the workgroup calls it (it holds barriers).
void build_subtree(uint child, uvec3 top, bool build, uint builder, uvec3 me) {
    uint base = builder * 64u;
    vec2 range = EMPTY_RANGE;
    uvec3 parent = top * 4u + me;
    if (build) {
        uvec3 below = dims_of_level(child);
        for (uint c = 0u; c < 8u; ++c) {
            uvec3 p = parent * 2u + corner(c);
            if (all(lessThan(p, below))) {
                range = merge(range, minmax_nodes[node_index(child, p)]);
            }
        }
        store(child + 1u, parent, range);
    }
    // Missing nodes hold the empty range, which merging ignores.
    s_ranges[base + me.x + 4u * (me.y + 4u * me.z)] = range;
    barrier();
    bool second = build && all(lessThan(me, uvec3(2u)));
    if (second) {
        range = EMPTY_RANGE;
        for (uint c = 0u; c < 8u; ++c) {
            uvec3 q = me * 2u + corner(c);
            range = merge(range, s_ranges[base + q.x + 4u * (q.y + 4u * q.z)]);
        }
        store(child + 2u, top * 2u + me, range);
    }
    barrier();
    if (second) {
        s_ranges[base + me.x + 4u * (me.y + 4u * me.z)] = range;
    }
    barrier();
    if (build && all(equal(me, uvec3(0u)))) {
        range = EMPTY_RANGE;
        for (uint c = 0u; c < 8u; ++c) {
            uvec3 q = corner(c);
            range = merge(range, s_ranges[base + q.x + 4u * (q.y + 4u * q.z)]);
        }
        store(child + 3u, top, range);
    }
}

void main() {
    uvec3 blocks = params.block_dims.xyz;
    uint invocation = gl_LocalInvocationIndex;
    vec2 range = block_range(invocation);
    uvec3 block = uvec3(gl_WorkGroupID.x * BLOCKS_PER_GROUP + invocation, gl_WorkGroupID.yz);
    if (invocation < BLOCKS_PER_GROUP && block.x < blocks.x) {
        minmax_nodes[block.x + blocks.x * (block.y + blocks.y * block.z)] = range;
    }
    if (params.level_count == 1u) {
        return;
    }
    // Level 0's writes reach the device before this workgroup counts them.
    memoryBarrierBuffer();
    barrier();
    // Builder b takes level-3 node b of the four this workgroup's blocks fall in.
    uint builder = invocation / 64u;
    uint local = invocation % 64u;
    uvec3 me = uvec3(local & 3u, (local >> 2) & 3u, local >> 4);
    uvec3 top = uvec3(gl_WorkGroupID.x * SUBTREES + builder, gl_WorkGroupID.yz / FAN_OUT);
    if (local == 0u) {
        s_builds[builder] = top.x * FAN_OUT < blocks.x && arrive(3u, top);
    }
    barrier();
    uint child = 0u;
    bool any_build = true;
    while (any_build) {
        // Other workgroups' nodes of level `child` are visible once their counts are seen.
        memoryBarrierBuffer();
        bool build = s_builds[builder];
        build_subtree(child, top, build, builder, me);
        bool chained = child + 3u < params.level_count - 1u;
        barrier();
        if (local == 0u) {
            // This subtree's top node reaches the device before it counts in the next.
            memoryBarrierBuffer();
            s_builds[builder] = build && chained && arrive(child + 6u, top / FAN_OUT);
        }
        barrier();
        any_build = false;
        for (uint b = 0u; b < SUBTREES; ++b) {
            any_build = any_build || s_builds[b];
        }
        top /= FAN_OUT;
        child += 3u;
        barrier();
    }
}
