// Subblock geometry shared by the region analysis and the extraction. Needs
// common/volume.glsl, iso/meshlets/params.glsl and iso/meshlets/buffers.glsl.

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

// The last sample of a subblock's box clipped to the volume (its cells lie before it).
uvec3 meshlet_box_end(uvec3 origin, uvec3 size) {
    return min(origin + size, params.volume_dims - 1u);
}

// Whether the grid edge from `p` one step along `axis` crosses iso (below is `< iso`).
bool meshlet_edge_crosses(uvec3 p, uint axis, float iso) {
    uvec3 q = p;
    q[axis] += 1u;
    return (volume_texel(volume_tex, ivec3(p)) < iso) != (volume_texel(volume_tex, ivec3(q)) < iso);
}

// Crossed edges owned by padding points (samples of the box lo ..= hi on a max face, x
// fastest) numbered first .. end in that order; only edges inside the box count.
uint meshlet_padding_crossings(uvec3 lo, uvec3 hi, uint first, uint end, float iso) {
    uvec3 points = hi - lo + 1u;
    uint count = 0u;
    for (uint j = first; j < end; ++j) {
        uvec3 p = lo + uvec3(j % points.x, (j / points.x) % points.y, j / (points.x * points.y));
        if (!any(equal(p, hi))) {
            continue;
        }
        for (uint axis = 0u; axis < 3u; ++axis) {
            if (p[axis] < hi[axis] && meshlet_edge_crosses(p, axis, iso)) {
                count += 1u;
            }
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
