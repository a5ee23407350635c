// The samples of a box of the volume with a one-sample apron, held in shared memory by one
// workgroup: the region analysis and the extraction read every value they need from here
// (cell cases, crossed edges, vertex values and gradients) instead of fetching each sample
// from the volume again for every cell, box and vertex that touches it. The compute path
// loads a block's box once for both stages; a mesh workgroup loads its subblock's box.
// Needs common/volume.glsl, common/mc_tables.glsl, common/mc_cell.glsl, common/exact.glsl,
// common/mc_vertex.glsl and iso/meshlets/params.glsl.

// The largest box, a block's cells plus one sample on each axis, and the apron on each side.
const uint MESHLET_SAMPLES_X = BLOCK_X + 3u;
const uint MESHLET_SAMPLES_Y = BLOCK_Y + 3u;
const uint MESHLET_SAMPLES_Z = BLOCK_Z + 3u;
shared float s_samples[MESHLET_SAMPLES_X * MESHLET_SAMPLES_Y * MESHLET_SAMPLES_Z];

// Where the held samples start in the volume (the apron may start at -1) and how many there
// are per axis; the same in every invocation. The compute path only ever holds a whole
// block's box, so there the size is a constant (the box at the volume's far faces held
// whole too, its samples past the volume clamped like the apron's): indexing and the load's
// divisions then take constants.
ivec3 held_first;
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
const uvec3 held_size = uvec3(MESHLET_SAMPLES_X, MESHLET_SAMPLES_Y, MESHLET_SAMPLES_Z);
#else
uvec3 held_size;
#endif

// Loads the samples of the box lo ..= hi and its apron; apron samples outside the volume hold
// its nearest border sample and are never read as values. Call from uniform control flow:
// ends with a barrier.
void meshlet_load_samples(uvec3 lo, uvec3 hi) {
    held_first = ivec3(lo) - 1;
#ifndef MESHLET_ANALYSIS_IN_WORKGROUP
    held_size = hi - lo + 3u;
#endif
    uint count = held_size.x * held_size.y * held_size.z;
    ivec3 last = ivec3(params.volume_dims) - 1;
    for (uint i = gl_LocalInvocationIndex; i < count; i += MESHLET_WORKGROUP) {
        ivec3 offset = ivec3(i % held_size.x, (i / held_size.x) % held_size.y,
                             i / (held_size.x * held_size.y));
        s_samples[i] = volume_texel(volume_tex, clamp(held_first + offset, ivec3(0), last));
    }
    barrier();
}

float meshlet_sample(uvec3 p) {
    uvec3 d = uvec3(ivec3(p) - held_first);
    return s_samples[(d.z * held_size.y + d.y) * held_size.x + d.x];
}

void meshlet_cell_corners(uvec3 cell, out float corners[8]) {
    for (uint c = 0u; c < 8u; ++c) {
        corners[c] = meshlet_sample(cell + mc_corner_offset(c));
    }
}

// mc_box_owned_crossings from the held samples (the apron holds every neighbour).
uint meshlet_owned_crossings(uvec3 p, uvec3 hi, float iso) {
    vec3 next = vec3(meshlet_sample(p + uvec3(1u, 0u, 0u)), meshlet_sample(p + uvec3(0u, 1u, 0u)),
                     meshlet_sample(p + uvec3(0u, 0u, 1u)));
    return mc_owned_crossings_of(p, hi, meshlet_sample(p), next, iso);
}

// mc_grid_gradient from the held samples.
vec3 meshlet_gradient(uvec3 p) {
    vec3 g;
    for (uint axis = 0u; axis < 3u; ++axis) {
        uvec3 lo;
        uvec3 hi;
        float inverse_span = mc_gradient_ends(p, axis, params.volume_dims, lo, hi);
        g[axis] = (meshlet_sample(hi) - meshlet_sample(lo)) * inverse_span;
    }
    return g;
}

// mc_exact_edge_vertex from the held samples.
void meshlet_edge_vertex(uvec3 start, uint axis, float iso, out vec3 position, out vec3 normal) {
    uvec3 end = start;
    end[axis] += 1u;
    mc_exact_vertex(start, axis, meshlet_sample(start), meshlet_sample(end),
                    meshlet_gradient(start), meshlet_gradient(end), iso, position, normal);
}
