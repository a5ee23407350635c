// The meshlet format on the GPU (tessera_data::meshlets::format): what extraction writes and
// drawing reads.

// tessera_data::meshlets::Meshlet: scalar arrays, not vec3, so std430 packs it in 19 words.
struct Meshlet {
    uint vertex_offset;
    uint vertex_count;
    uint triangle_offset;
    uint triangle_count;
    float aabb_min[3];
    float aabb_max[3];
    uint block_origin[3];
    uint subblock_origin[3];
    uint subblock_size[3];
};

// Totals reserved so far (they keep counting past the capacities) and MESHLET_OVERFLOW_* bits.
struct MeshletCounters {
    uint meshlets;
    uint vertices;
    uint triangles;
    uint overflow;
};

// A block's reservation outran a capacity: grow the buffers and extract again.
const uint MESHLET_OVERFLOW_CAPACITY = 1u;
// An extraction counted otherwise than its region analysis: a defect, never a retry.
const uint MESHLET_OVERFLOW_MISMATCH = 2u;
