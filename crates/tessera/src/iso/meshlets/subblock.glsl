// Subblock geometry shared by the region analysis and the extraction. Needs
// common/volume.glsl, common/mc_edges.glsl and iso/meshlets/{params,buffers,samples}.glsl.

// Cell of Morton code `code` inside its block (tessera_data::meshlets::morton: bits
// x0 y0 z0 x1 y1 z1 x2 y2).
uvec3 meshlet_cell_of_code(uint code) {
    return uvec3((code & 1u) | ((code >> 2) & 2u) | ((code >> 4) & 4u),
                 ((code >> 1) & 1u) | ((code >> 3) & 2u) | ((code >> 5) & 4u),
                 ((code >> 2) & 1u) | ((code >> 4) & 2u));
}

uvec3 meshlet_block_origin(uint block_id) {
    uvec3 d = params.block_dims;
    uvec3 block = uvec3(block_id % d.x, (block_id / d.x) % d.y, block_id / (d.x * d.y));
    return block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);
}

// Crossed edges owned by padding points (samples of the box lo ..= hi on a max face, x
// fastest) numbered first .. end in that order; only edges inside the box count.
uint meshlet_padding_crossings(uvec3 lo, uvec3 hi, uint first, uint end, float iso) {
    uvec3 points = hi - lo + 1u;
    uint count = 0u;
    for (uint j = first; j < end; ++j) {
        uvec3 p = mc_box_point(lo, points, j);
        if (any(equal(p, hi))) {
            count += bitCount(meshlet_owned_crossings(p, hi, iso));
        }
    }
    return count;
}

// Samples in the box lo ..= hi; none when the box holds no cell.
uint meshlet_box_points(uvec3 lo, uvec3 hi) {
    if (any(greaterThanEqual(lo, hi))) {
        return 0u;
    }
    uvec3 points = hi - lo + 1u;
    return points.x * points.y * points.z;
}
