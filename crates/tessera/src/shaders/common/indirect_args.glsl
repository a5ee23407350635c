// Indirect dispatch arguments grown by the passes that fill a list, in place of a pass after
// them that turns the final count into arguments: a dispatch and a barrier fewer per list.

#ifndef COMMON_INDIRECT_ARGS_GLSL
#define COMMON_INDIRECT_ARGS_GLSL

// Workgroups along x that every Vulkan device accepts (the least maxComputeWorkGroupCount[0]
// the specification allows).
const uint INDIRECT_MAX_GROUPS_X = 65535u;

// Grows `args` (uint[3] indirect dispatch arguments, zero or (0, 1, 1) before the list's first
// writer) to cover the first `items` items at `items_per_group` per workgroup, on a 2-D grid of
// workgroups when one row would pass INDIRECT_MAX_GROUPS_X (the reading pass flattens the grid
// and skips the tail of its last row). Each writer passes the end of the range it reserved; the
// arguments are monotone in `items`, so once every writer is done they cover the largest end,
// the final count, in whatever order the writers ran. A macro: GLSL's atomics must name the
// buffer member itself.
#define GROW_INDIRECT_ARGS(args, items, items_per_group) {                                   \
    uint grow_groups = ((items) + (items_per_group) - 1u) / (items_per_group);                  \
    atomicMax(args[0], min(grow_groups, INDIRECT_MAX_GROUPS_X));                                \
    atomicMax(args[1], (grow_groups + INDIRECT_MAX_GROUPS_X - 1u) / INDIRECT_MAX_GROUPS_X);     \
    atomicMax(args[2], 1u);                                                                     \
}

#endif
