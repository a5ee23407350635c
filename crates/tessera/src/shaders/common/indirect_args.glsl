// Indirect dispatch arguments grown by the passes that fill a list, in place of a pass after
// them that turns the final count into arguments: a dispatch and a barrier fewer per list.

#ifndef COMMON_INDIRECT_ARGS_GLSL
#define COMMON_INDIRECT_ARGS_GLSL

// Workgroups along x that every Vulkan device accepts (the least maxComputeWorkGroupCount[0]
// the specification allows).
const uint INDIRECT_MAX_GROUPS_X = 65535u;

// Grows the indirect dispatch arguments `x`, `y`, `z` (zero or (0, 1, 1) before the list's
// first writer) to cover the first `items` items at `items_per_group` per workgroup, on a 2-D grid of
// workgroups when one row would pass INDIRECT_MAX_GROUPS_X (the reading pass flattens the grid
// and skips the tail of its last row). Each writer passes the end of the range it reserved; the
// arguments are monotone in `items`, so once every writer is done they cover the largest end,
// the final count, in whatever order the writers ran. A macro: GLSL's atomics must name the
// buffer member itself.
#define GROW_INDIRECT_ARGS(x, y, z, items, items_per_group) {                                \
    uint grow_groups = ((items) + (items_per_group) - 1u) / (items_per_group);                  \
    atomicMax(x, min(grow_groups, INDIRECT_MAX_GROUPS_X));                                      \
    atomicMax(y, (grow_groups + INDIRECT_MAX_GROUPS_X - 1u) / INDIRECT_MAX_GROUPS_X);           \
    atomicMax(z, 1u);                                                                           \
}

// The same for a uint[3] of arguments.
#define GROW_INDIRECT_ARGS3(args, items, items_per_group) \
    GROW_INDIRECT_ARGS(args[0], args[1], args[2], items, items_per_group)

#endif
