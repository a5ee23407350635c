// The samples of a box of the volume with a one-sample apron, held in shared memory by one
// workgroup: cases, crossings, vertices and gradients read every value they need from here
// instead of fetching each sample from the volume again for every cell, box and vertex that
// touches it. Every value is the volume's own, so what is made from them is what the volume
// gives. The includer defines HELD_SAMPLES_MAX (the most samples a box holds, apron included),
// HELD_SAMPLES_LOADERS (the workgroup's invocations, which share the load) and, where every
// box it holds has one size, HELD_SAMPLES_SIZE (a uvec3): indexing and the load's divisions
// then take constants. Needs common/volume.glsl, common/mc_tables.glsl and
// common/mc_cell.glsl; the includer declares `volume_tex`.

#ifndef COMMON_HELD_SAMPLES_GLSL
#define COMMON_HELD_SAMPLES_GLSL

shared float held_samples[HELD_SAMPLES_MAX];

// Where the held samples start in the volume (the apron may start at -1) and how many there
// are per axis; the same in every invocation.
ivec3 held_first;
#ifdef HELD_SAMPLES_SIZE
const uvec3 held_size = HELD_SAMPLES_SIZE;
#else
uvec3 held_size;
#endif

// Loads the samples of the box lo ..= hi of a volume of `dims` samples, and its apron; apron
// samples outside the volume hold its nearest border sample and are never read as values
// (gradients clamp to the volume). Call from uniform control flow: ends with a barrier.
void held_samples_load(uvec3 lo, uvec3 hi, uvec3 dims) {
    held_first = ivec3(lo) - 1;
#ifndef HELD_SAMPLES_SIZE
    held_size = hi - lo + 3u;
#endif
    uint count = held_size.x * held_size.y * held_size.z;
    ivec3 last = ivec3(dims) - 1;
    for (uint i = gl_LocalInvocationIndex; i < count; i += HELD_SAMPLES_LOADERS) {
        ivec3 offset = ivec3(i % held_size.x, (i / held_size.x) % held_size.y,
                             i / (held_size.x * held_size.y));
        held_samples[i] = volume_texel(volume_tex, clamp(held_first + offset, ivec3(0), last));
    }
    barrier();
}

float held_sample(uvec3 p) {
    uvec3 d = uvec3(ivec3(p) - held_first);
    return held_samples[(d.z * held_size.y + d.y) * held_size.x + d.x];
}

void held_cell_corners(uvec3 cell, out float corners[8]) {
    for (uint c = 0u; c < 8u; ++c) {
        corners[c] = held_sample(cell + mc_corner_offset(c));
    }
}

// mc_grid_gradient from the held samples.
vec3 held_gradient(uvec3 p, uvec3 dims) {
    vec3 g;
    for (uint axis = 0u; axis < 3u; ++axis) {
        uvec3 lo;
        uvec3 hi;
        float inverse_span = mc_gradient_ends(p, axis, dims, lo, hi);
        g[axis] = (held_sample(hi) - held_sample(lo)) * inverse_span;
    }
    return g;
}

// mc_edge_vertex from the held samples.
void held_edge_vertex(uvec3 cell, uint edge, float iso, uvec3 dims, out vec3 position,
                      out vec3 normal) {
    uint corners = MC_EDGE_CORNERS[edge];
    uvec3 pa = cell + mc_corner_offset(corners & 15u);
    uvec3 pb = cell + mc_corner_offset(corners >> 4);
    mc_edge_vertex_of(pa, pb, held_sample(pa), held_sample(pb), held_gradient(pa, dims),
                      held_gradient(pb, dims), iso, position, normal);
}

#endif
