// What every meshlet draw pass reads: the meshlet buffers an extraction (or an upload) left,
// and the frame's draw counters. Needs iso/meshlet_draw/params.glsl.
#include "iso/meshlets/format.glsl"
#include "common/frustum.glsl"

layout(binding = 0) readonly buffer Counters { MeshletCounters counters; };
layout(binding = 1) readonly buffer Meshlets { Meshlet meshlets[]; };
layout(binding = 2) readonly buffer Positions { float positions[]; };
layout(binding = 3) readonly buffer Normals { float normals[]; };
layout(binding = 4) readonly buffer LocalIndices { uint local_index_words[]; };
// Meshlets that passed culling and the triangles they hold (all of them, also those a full
// compute list could not take).
layout(binding = 5) buffer DrawCounters { uint meshlets_drawn; uint triangles_drawn; };

// Meshlets to draw: none after an extraction that overflowed its buffers (some reserved
// meshlets were never written; the host grows the buffers and extracts again).
uint meshlets_to_draw() {
    return counters.overflow != 0u ? 0u : counters.meshlets;
}

vec3 meshlet_position(uint v) {
    return vec3(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]);
}

vec3 meshlet_normal(uint v) {
    return vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]);
}

// Local index `i` of the meshlet mesh: bytes, four to a word.
uint meshlet_local_index(uint i) {
    return (local_index_words[i >> 2u] >> (8u * (i & 3u))) & 0xffu;
}

// The meshlet this workgroup handles, counted over a grid of workgroups spread in x and y.
uint meshlet_group() {
    return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
}

// The box meshlet `m` is culled by (grid units), as params.bounds picks; false for none. The
// implicit box is its subblock's cells; a meshlet without one (the offline reference's) falls
// back to its explicit AABB.
bool meshlet_box(Meshlet m, out vec3 lo, out vec3 hi) {
    lo = vec3(m.aabb_min[0], m.aabb_min[1], m.aabb_min[2]);
    hi = vec3(m.aabb_max[0], m.aabb_max[1], m.aabb_max[2]);
    uvec3 size = meshlet_subblock_size(m);
    if (params.bounds == MESHLET_BOUNDS_IMPLICIT && size.x != 0u) {
        lo = vec3(meshlet_subblock_origin(m));
        hi = lo + vec3(size);
    }
    return params.bounds != MESHLET_BOUNDS_NONE;
}

// Whether meshlet `m` may reach the view (common/frustum.glsl).
bool meshlet_in_frustum(Meshlet m) {
    vec3 lo;
    vec3 hi;
    return !meshlet_box(m, lo, hi) || box_in_frustum(params.grid_to_clip, lo, hi);
}
