// The meshlet format on the GPU (tessera_data::meshlets::format): what extraction writes and
// drawing reads.

// tessera_data::meshlets::Meshlet: scalar arrays, not vec3, so std430 packs it in 11 words;
// counts and subblock packed as there (read them with the functions below).
struct Meshlet {
    uint vertex_offset;
    uint triangle_offset;
    uint counts;       // vertices | triangles << 16
    float aabb_min[3];
    float aabb_max[3];
    uint subblock[2];  // minimum cell x | y << 16, z | size x << 16 | size y << 20 | size z << 24
};

Meshlet meshlet_new(uint vertex_offset, uint vertex_count, uint triangle_offset,
                    uint triangle_count, vec3 aabb_min, vec3 aabb_max, uvec3 subblock_origin,
                    uvec3 subblock_size) {
    return Meshlet(vertex_offset, triangle_offset, vertex_count | triangle_count << 16,
                   float[3](aabb_min.x, aabb_min.y, aabb_min.z),
                   float[3](aabb_max.x, aabb_max.y, aabb_max.z),
                   uint[2](subblock_origin.x | subblock_origin.y << 16,
                           subblock_origin.z | subblock_size.x << 16 | subblock_size.y << 20
                               | subblock_size.z << 24));
}

uint meshlet_vertex_count(Meshlet m) {
    return m.counts & 0xffffu;
}

uint meshlet_triangle_count(Meshlet m) {
    return m.counts >> 16;
}

uvec3 meshlet_subblock_origin(Meshlet m) {
    return uvec3(m.subblock[0] & 0xffffu, m.subblock[0] >> 16, m.subblock[1] & 0xffffu);
}

// Zero for a meshlet without a cell box (the offline reference's).
uvec3 meshlet_subblock_size(Meshlet m) {
    return uvec3(m.subblock[1] >> 16, m.subblock[1] >> 20, m.subblock[1] >> 24) & 15u;
}

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
