// Adds one ray's traversal counts to the stats buffer (STAT_* indices from Rust). Steps are a
// 64-bit count in two words: large images march billions of steps.
// Needs buffers.glsl and traverse.glsl.

void add_stat(uint index, uint value) {
    if (value != 0u) {
        atomicAdd(stats[index], value);
    }
}

void add_counts(TraversalCounts counts) {
    add_stat(STAT_RAYS, 1u);
    add_stat(STAT_SEGMENTS, counts.segments);
    uint before = atomicAdd(stats[STAT_STEPS_LOW], counts.steps);
    if (before + counts.steps < before) {
        atomicAdd(stats[STAT_STEPS_HIGH], 1u);
    }
    add_stat(STAT_DEAD_ENDS, counts.dead_ends);
    add_stat(STAT_STEP_LIMITS, counts.step_limits);
    add_stat(STAT_BACKWARD_STEPS, counts.backward_steps);
    add_stat(STAT_UNMATCHED_EXITS, counts.unmatched_exits);
}
