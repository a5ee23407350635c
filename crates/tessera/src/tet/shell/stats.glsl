// Adds one ray's traversal counts to the stats buffer (STAT_* indices from Rust). Steps are a
// 64-bit count in two words: large images march billions of steps.
// Needs buffers.glsl and traverse.glsl.

void add_stat(uint index, uint value) {
    if (value != 0u) {
        atomicAdd(stats[index], value);
    }
}

// Adds `value` to the 64-bit count in words `low` and `low + 1`.
void add_wide_stat(uint low, uint value) {
    if (value == 0u) {
        return;
    }
    uint before = atomicAdd(stats[low], value);
    if (before + value < before) {
        atomicAdd(stats[low + 1u], 1u);
    }
}

void add_counts(TraversalCounts counts) {
    add_stat(STAT_RAYS, 1u);
    add_stat(STAT_SEGMENTS, counts.segments);
    add_wide_stat(STAT_STEPS_LOW, counts.steps);
    add_stat(STAT_DEAD_ENDS, counts.dead_ends);
    add_stat(STAT_STEP_LIMITS, counts.step_limits);
    add_stat(STAT_BACKWARD_STEPS, counts.backward_steps);
    add_stat(STAT_UNMATCHED_EXITS, counts.unmatched_exits);
}

// Adds `rays` secondary rays of one kind (STAT_SHADOW_RAYS or STAT_AO_RAYS) and what their
// traversals counted.
void add_secondary_counts(uint kind, uint rays, TraversalCounts counts) {
    add_stat(kind, rays);
    add_wide_stat(STAT_SECONDARY_STEPS_LOW, counts.steps);
    add_stat(STAT_SECONDARY_GUARD_HITS, counts.dead_ends + counts.step_limits);
}
