// The meshlet extraction's held samples (common/held_samples.glsl): the region analysis and
// the extraction read every value they need from there. The compute path loads a block's box
// once for both stages, and only ever holds a whole block's box (the box at the volume's far
// faces held whole too, its samples past the volume clamped like the apron's), so there the
// size is a constant; a mesh workgroup loads its subblock's box. Needs common/volume.glsl,
// common/mc_tables.glsl, common/mc_cell.glsl, common/exact.glsl, common/mc_vertex.glsl and
// iso/meshlets/params.glsl.

#define HELD_SAMPLES_MAX ((BLOCK_X + 3u) * (BLOCK_Y + 3u) * (BLOCK_Z + 3u))
#define HELD_SAMPLES_LOADERS MESHLET_WORKGROUP
#ifdef MESHLET_ANALYSIS_IN_WORKGROUP
#define HELD_SAMPLES_SIZE uvec3(BLOCK_X + 3u, BLOCK_Y + 3u, BLOCK_Z + 3u)
#endif
#include "common/held_samples.glsl"

// mc_box_owned_crossings from the held samples (the apron holds every neighbour).
uint meshlet_owned_crossings(uvec3 p, uvec3 hi, float iso) {
    vec3 next = vec3(held_sample(p + uvec3(1u, 0u, 0u)), held_sample(p + uvec3(0u, 1u, 0u)),
                     held_sample(p + uvec3(0u, 0u, 1u)));
    return mc_owned_crossings_of(p, hi, held_sample(p), next, iso);
}

// mc_exact_edge_vertex from the held samples.
void meshlet_edge_vertex(uvec3 start, uint axis, float iso, out vec3 position, out vec3 normal) {
    uvec3 end = start;
    end[axis] += 1u;
    mc_exact_vertex(start, axis, held_sample(start), held_sample(end),
                    held_gradient(start, params.volume_dims), held_gradient(end, params.volume_dims),
                    iso, position, normal);
}
