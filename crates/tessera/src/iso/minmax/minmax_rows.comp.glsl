#version 460
// Every level of the min-max octree in one dispatch, from a buffer of the samples (x
// fastest, packed as the volume holds them) rather than the 3-D texture.
//
// Level 0: a workgroup takes 32 blocks along x of one block row; lane i takes block i and
// walks the block's rows of samples (y, z), eight row walkers per block. Along a row the 32
// lanes read neighbouring stretches, so a warp's loads fall in a few cache lines and every
// sample is fetched from memory about once. A walker issues all its rows' loads before it
// merges any (the bounds are constants), so each invocation keeps many loads in flight: a
// walk that merged each word before loading the next waited on memory once per word. The
// eight walkers of a block meet once in shared memory.
//
// Levels above: each level-3 node (8×8×8 blocks) counts the workgroups that have written
// their blocks of it; the workgroup that completes the count builds levels 1–3 of that node
// (64 invocations, as `minmax_levels.comp.glsl` does a node), and so up, three levels at a
// time, each level-3k node counted by the level-3(k-1) nodes below it, until the root. The
// last arrival resets its counter, so the counters are zero for the next build. One
// dispatch replaces a level pass and a barrier per three levels, the build's fixed cost on
// volumes of a few hundred MB. Samples are read as 32-bit words, so the buffer holds whole
// words; SAMPLE_BYTES (1, 2 or 4) and SAMPLE_FLOAT describe the samples.
#extension GL_EXT_control_flow_attributes : require

layout(local_size_x = 32, local_size_y = 8) in;
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
const uint WALKERS = 8u;
const uint BLOCK_ROWS = (BLOCK_Y + 1u) * (BLOCK_Z + 1u);
const uint ROWS_PER_WALKER = (BLOCK_ROWS + WALKERS - 1u) / WALKERS;
// Words a row of BLOCK_X + 1 samples spans when it starts at any sample of a word.
const uint ROW_WORDS = ((BLOCK_X + 1u) * SAMPLE_BYTES + 4u - SAMPLE_BYTES + 3u) / 4u;
// Nodes of the level below a level-3k node, per axis.
const uint FAN_OUT = 8u;
// The level-3 nodes one workgroup's 32 blocks fall in, and so the subtree builders.
const uint SUBTREES = 32u / FAN_OUT;

// Level 0's walkers' partial ranges, then each subtree builder's 64 ranges.
shared vec2 s_ranges[WALKERS * 32u];
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

// Level 0 of this invocation's block, merged over its walkers (valid in walker 0).
vec2 block_range(uvec3 block, uint lane, uint walker) {
    uvec3 dims = params.volume_dims.xyz;
    // The block's samples: its cells' corners, up to the next block's first sample.
    uvec3 lo = block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
    uvec3 hi = min(lo + uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z), dims - 1u);
    uint rows_y = hi.y - lo.y + 1u;
    uint rows = rows_y * (hi.z - lo.z + 1u);
    bool inside = block.x < params.block_dims.x;
    uint words[ROWS_PER_WALKER][ROW_WORDS];
    uint first[ROWS_PER_WALKER];
    [[unroll]] for (uint i = 0u; i < ROWS_PER_WALKER; ++i) {
        uint r = walker + i * WALKERS;
        bool row = inside && r < rows;
        uint y = lo.y + r % rows_y;
        uint z = lo.z + r / rows_y;
        first[i] = (z * dims.y + y) * dims.x + lo.x;  // flat sample index
        uint last_word = (first[i] + hi.x - lo.x) / SAMPLES_PER_WORD;
        [[unroll]] for (uint j = 0u; j < ROW_WORDS; ++j) {
            uint w = first[i] / SAMPLES_PER_WORD + j;
            words[i][j] = row && w <= last_word ? sample_words[w] : 0u;
        }
    }
    vec2 range = EMPTY_RANGE;
    [[unroll]] for (uint i = 0u; i < ROWS_PER_WALKER; ++i) {
        if (inside && walker + i * WALKERS < rows) {
            uint first_word = first[i] / SAMPLES_PER_WORD;
            [[unroll]] for (uint j = 0u; j < ROW_WORDS; ++j) {
                [[unroll]] for (uint k = 0u; k < SAMPLES_PER_WORD; ++k) {
                    uint s = (first_word + j) * SAMPLES_PER_WORD + k;
                    if (s >= first[i] && s <= first[i] + hi.x - lo.x) {
                        range = merge(range, vec2(sample_of_word(words[i][j], k)));
                    }
                }
            }
        }
    }
    s_ranges[walker * 32u + lane] = range;
    barrier();
    if (walker == 0u) {
        for (uint i = 1u; i < WALKERS; ++i) {
            range = merge(range, s_ranges[i * 32u + lane]);
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
    uint lane = gl_LocalInvocationID.x;
    uint walker = gl_LocalInvocationID.y;
    uvec3 block = uvec3(gl_WorkGroupID.x * 32u + lane, gl_WorkGroupID.y, gl_WorkGroupID.z);
    vec2 range = block_range(block, lane, walker);
    if (walker == 0u && block.x < blocks.x) {
        minmax_nodes[block.x + blocks.x * (block.y + blocks.y * block.z)] = range;
    }
    if (params.level_count == 1u) {
        return;
    }
    // Level 0's writes reach the device before this workgroup counts them.
    memoryBarrierBuffer();
    barrier();
    // Builder b takes level-3 node b of the four this workgroup's blocks fall in.
    uint invocation = walker * 32u + lane;
    uint builder = invocation / 64u;
    uint local = invocation % 64u;
    uvec3 me = uvec3(local & 3u, (local >> 2) & 3u, local >> 4);
    uvec3 top = uvec3(gl_WorkGroupID.x * SUBTREES + builder, block.yz / FAN_OUT);
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
