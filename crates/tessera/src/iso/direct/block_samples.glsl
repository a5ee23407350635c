// The samples of one 8×8×4 block's cells with a one-sample apron, loaded into shared memory
// once by the extraction's workgroup: each sample is read by up to eight cells' cases and by
// the gradients of every vertex near it, and fetching it from the volume each time costs more
// than one load and a barrier. Every value is the volume's own, so cases, rows and vertices
// are those the volume gives. Needs common/volume.glsl, common/mc_tables.glsl and
// common/mc_cell.glsl; the includer declares `volume_tex`.

const uvec3 BLOCK_SAMPLES = uvec3(BLOCK_X + 3u, BLOCK_Y + 3u, BLOCK_Z + 3u);
shared float block_samples[BLOCK_SAMPLES.x * BLOCK_SAMPLES.y * BLOCK_SAMPLES.z];

// The grid point held first (one before the block's first cell; -1 at the volume's start).
ivec3 block_samples_first;

// Loads the samples of `block` (in blocks) of a volume of `dims` samples; points past the
// volume hold its nearest border sample and are never read (gradients clamp to the volume).
// Call from uniform control flow: ends with a barrier.
void block_samples_load(uvec3 block, uvec3 dims) {
    block_samples_first = ivec3(block * uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z)) - 1;
    ivec3 last = ivec3(dims) - 1;
    uint count = BLOCK_SAMPLES.x * BLOCK_SAMPLES.y * BLOCK_SAMPLES.z;
    for (uint i = gl_LocalInvocationIndex; i < count; i += gl_WorkGroupSize.x) {
        ivec3 offset = ivec3(i % BLOCK_SAMPLES.x, (i / BLOCK_SAMPLES.x) % BLOCK_SAMPLES.y,
                             i / (BLOCK_SAMPLES.x * BLOCK_SAMPLES.y));
        block_samples[i] = volume_texel(volume_tex, clamp(block_samples_first + offset, ivec3(0), last));
    }
    barrier();
}

float block_sample(uvec3 p) {
    uvec3 d = uvec3(ivec3(p) - block_samples_first);
    return block_samples[(d.z * BLOCK_SAMPLES.y + d.y) * BLOCK_SAMPLES.x + d.x];
}

void block_cell_corners(uvec3 cell, out float corners[8]) {
    for (uint c = 0u; c < 8u; ++c) {
        corners[c] = block_sample(cell + mc_corner_offset(c));
    }
}

// mc_grid_gradient from the held samples.
vec3 block_gradient(uvec3 p, uvec3 dims) {
    vec3 g;
    for (uint axis = 0u; axis < 3u; ++axis) {
        uvec3 lo;
        uvec3 hi;
        float inverse_span = mc_gradient_ends(p, axis, dims, lo, hi);
        g[axis] = (block_sample(hi) - block_sample(lo)) * inverse_span;
    }
    return g;
}

// mc_edge_vertex from the held samples.
void block_edge_vertex(uvec3 cell, uint edge, float iso, uvec3 dims, out vec3 position,
                       out vec3 normal) {
    uint corners = MC_EDGE_CORNERS[edge];
    uvec3 pa = cell + mc_corner_offset(corners & 15u);
    uvec3 pb = cell + mc_corner_offset(corners >> 4);
    mc_edge_vertex_of(pa, pb, block_sample(pa), block_sample(pb), block_gradient(pa, dims),
                      block_gradient(pb, dims), iso, position, normal);
}
