// What a task workgroup hands its mesh workgroups: the block, its occupied cells in
// ascending id order (four 8-bit ids per word), and the cell lists, each at most
// DIRECT_MAX_CELLS cells and DIRECT_MAX_VERTICES vertices.
struct TaskPayload {
    uvec3 block;
    uint cell_words[64];   // cell id i in byte (i & 3) of word i >> 2
    uint lists[32];        // first cell index | cell count << 16
};
