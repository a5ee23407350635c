// Push constants of the PMB passes (host side: PmbParams).
layout(push_constant) uniform PmbParams {
    uvec3 volume_dims;      // samples per axis
    float isovalue;
    uvec3 block_dims;       // PMB blocks per axis
    uint vertex_capacity;   // vertices the output holds
    uvec3 node_dims;        // min-max octree nodes per axis on level 0 (BLOCK_X×BLOCK_Y×BLOCK_Z cells)
    uint triangle_capacity; // triangles the output holds
} params;

const uvec3 PMB_BLOCK = uvec3(PMB_BLOCK_X, PMB_BLOCK_Y, PMB_BLOCK_Z);

// The coordinate of PMB block `id` (x fastest).
uvec3 pmb_block_of(uint id) {
    uvec3 d = params.block_dims;
    return uvec3(id % d.x, (id / d.x) % d.y, id / (d.x * d.y));
}
