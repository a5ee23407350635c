// Raster occlusion culling over regions of 8×8×8 cells (paper D, §3.5): a region is two
// 8×8×4 blocks stacked in z. Needs BLOCK_X/Y/Z and iso/direct/params.glsl.

const uvec3 REGION_CELLS = uvec3(BLOCK_X, BLOCK_Y, 2u * BLOCK_Z);

uvec3 cull_block_dims(uvec3 dims) {
    return (dims - 2u) / uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z) + 1u;
}

uvec3 cull_region_dims(uvec3 dims) {
    return (dims - 2u) / REGION_CELLS + 1u;
}

uint cull_region_count(uvec3 dims) {
    uvec3 r = cull_region_dims(dims);
    return r.x * r.y * r.z;
}

uvec3 cull_region_coords(uint region, uvec3 dims) {
    uvec3 r = cull_region_dims(dims);
    return uvec3(region % r.x, (region / r.x) % r.y, region / (r.x * r.y));
}

// Linear index of block `half` (0 or 1) of a region, or ~0u where the volume ends.
uint cull_region_block(uint region, uint half_index, uvec3 dims) {
    uvec3 b = cull_region_coords(region, dims) * uvec3(1u, 1u, 2u) + uvec3(0u, 0u, half_index);
    uvec3 bd = cull_block_dims(dims);
    return b.z < bd.z ? b.x + bd.x * (b.y + bd.y * b.z) : ~0u;
}
