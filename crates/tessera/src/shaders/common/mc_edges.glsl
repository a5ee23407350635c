// Vertex ownership of Parallel Marching Blocks, shared by the extractions that give each
// crossed grid edge of a box of cells one vertex (PMB and the meshlet extraction; CPU:
// tessera_data::meshlets::subblock). The grid edge from sample `p` one step along an axis
// belongs to the cell whose minimum corner is `p`; the box's cells are its core, and the
// edges on its max faces belong to padding points one layer beyond. Every crossed edge of
// the closed box is an edge of some occupied core cell, so each vertex is used and none is
// repeated. Needs common/volume.glsl and common/mc_tables.glsl.

// Crossed edges a cell of case `case_index` owns, those from corner 0 to corners 1, 2 and 4:
// bit `axis` set for each (as mc_owned_crossings_of gives them for a cell inside its box).
uint mc_case_owned_mask(uint case_index) {
    uint mask = 0u;
    for (uint axis = 0u; axis < 3u; ++axis) {
        mask |= ((case_index ^ (case_index >> (1u << axis))) & 1u) << axis;
    }
    return mask;
}

uint mc_case_owned_crossings(uint case_index) {
    return bitCount(mc_case_owned_mask(case_index));
}

// The crossed edges owned by sample `p` (value `value`) that lie inside the box ending at
// sample `hi`: bit `axis` set for each. `next[axis]` is the value one step along `axis`; it
// is read only where that edge lies inside the box.
uint mc_owned_crossings_of(uvec3 p, uvec3 hi, float value, vec3 next, float iso) {
    uint mask = 0u;
    for (uint axis = 0u; axis < 3u; ++axis) {
        if (p[axis] < hi[axis] && (next[axis] < iso) != (value < iso)) {
            mask |= 1u << axis;
        }
    }
    return mask;
}

// mc_owned_crossings_of with the values read from the volume (none past the box).
uint mc_box_owned_crossings(VOLUME_SAMPLER vol, uvec3 p, uvec3 hi, float iso) {
    float value = volume_texel(vol, ivec3(p));
    vec3 next = vec3(value);
    for (uint axis = 0u; axis < 3u; ++axis) {
        if (p[axis] < hi[axis]) {
            uvec3 q = p;
            q[axis] += 1u;
            next[axis] = volume_texel(vol, ivec3(q));
        }
    }
    return mc_owned_crossings_of(p, hi, value, next, iso);
}

// The owner of edge `edge` of `cell`: the sample at the edge's start and the edge's axis.
void mc_edge_owner(uvec3 cell, uint edge, out uvec3 start, out uint axis) {
    uint corners = MC_EDGE_CORNERS[edge];
    uint first = corners & 15u;
    axis = findLSB(first ^ (corners >> 4));
    start = cell + mc_corner_offset(first);
}

// The last sample of the box of `size` cells from `origin`, clipped to a volume of `dims`
// samples (its cells lie before it).
uvec3 mc_box_end(uvec3 origin, uvec3 size, uvec3 dims) {
    return min(origin + size, dims - 1u);
}

// Sample `j` of a box from `lo` of `points` samples per axis, x fastest.
uvec3 mc_box_point(uvec3 lo, uvec3 points, uint j) {
    return lo + uvec3(j % points.x, (j / points.x) % points.y, j / (points.x * points.y));
}
