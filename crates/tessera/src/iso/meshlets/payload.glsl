// What the region analysis hands the extraction of one block's meshlets: the task payload on
// the mesh-shader path, shared memory on the compute path (tessera_data::meshlets::gpu_layout).

// The 2×2×2 eighths of a block (MESHLET_EIGHTH_CELLS cells each), the smallest subblocks. The
// workgroup (MESHLET_WORKGROUP, from the host) has one invocation per eighth on the task/mesh
// path, as in the paper, and several on the compute path.
#define MESHLET_EIGHTHS (BLOCK_X * BLOCK_Y * BLOCK_Z / MESHLET_EIGHTH_CELLS)

// One subblock of the partition, offsets relative to the block's reservation.
struct MeshletSubblock {
    uint codes;      // first Morton code | code count << 16
    uint offsets;    // first vertex | first triangle << 16
    uint counts;     // vertices | triangles << 16, as the analysis counted them
    uint cells;      // first entry in `cells` | occupied cell count << 16
};

struct MeshletPayload {
    uint block;          // index into the occupied-block list
    uint base_meshlet;
    uint base_vertex;
    uint base_triangle;  // a multiple of 4: no two meshlets share a word of local indices
    uint subblock_count;
    // At most one subblock per eighth.
    MeshletSubblock subblocks[MESHLET_EIGHTHS];
    // Morton codes of the block's occupied cells in order, a byte each: the cells of each
    // subblock are a run of them.
    uint cells[BLOCK_X * BLOCK_Y * BLOCK_Z / 4u];
};
