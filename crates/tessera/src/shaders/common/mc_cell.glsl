// Marching-cubes work on single cells, shared by every extraction path. Needs
// common/volume.glsl and common/mc_tables.glsl; conventions are tessera_data::mc_tables'.

// Case index of a cell whose corners hold `corners` (in corner order): bit c set when corner
// c is below iso.
uint mc_case_of_corners(float corners[8], float iso) {
    uint case_index = 0u;
    for (uint c = 0u; c < 8u; ++c) {
        case_index |= uint(corners[c] < iso) << c;
    }
    return case_index;
}

// Case index of the cell whose minimum corner is `cell`.
uint mc_cell_case(VOLUME_SAMPLER vol, uvec3 cell, float iso) {
    uint case_index = 0u;
    for (uint c = 0u; c < 8u; ++c) {
        float v = volume_texel(vol, ivec3(cell + mc_corner_offset(c)));
        case_index |= uint(v < iso) << c;
    }
    return case_index;
}

#ifndef MC_ASYMPTOTIC_DECIDER
#error "MC_ASYMPTOTIC_DECIDER (the ambiguity rule) comes from tessera::config::marching_cubes_defines"
#endif

// The table row of a cell of case `case_index` whose corners hold `corners`: its ambiguous
// faces cut by the asymptotic decider, or with MC_ASYMPTOTIC_DECIDER 0 by VTK's rule (above
// corners always separated, the case's first row). Repeats
// tessera_data::mc_ambiguity::saddle_is_above exactly: the face's corners in the face's
// order, so both cells sharing a face decide alike, and the same rounded differences and
// products.
uint mc_row_of_corners(float corners[8], uint case_index, float iso) {
    uint choice = 0u;
#if MC_ASYMPTOTIC_DECIDER
    uint ambiguous = mc_ambiguous_faces(case_index);
    uint k = 0u;
    for (uint f = 0u; f < 6u; ++f) {
        if ((ambiguous & (1u << f)) == 0u) {
            continue;
        }
        uint face = MC_FACE_CORNERS[f];
        precise float d[4];
        for (uint j = 0u; j < 4u; ++j) {
            d[j] = corners[(face >> (4u * j)) & 15u] - iso;
        }
        precise float main_product = d[0] * d[3];
        precise float anti_product = d[1] * d[2];
        bool main_below = ((case_index >> (face & 15u)) & 1u) == 1u;
        bool joined = main_below ? anti_product >= main_product : main_product >= anti_product;
        choice |= uint(joined) << k;
        k += 1u;
    }
#endif
    return mc_first_row(case_index) + choice;
}

// The table row of `cell` (of case `case_index`); reads the corners only where a face is
// ambiguous.
uint mc_cell_row(VOLUME_SAMPLER vol, uvec3 cell, uint case_index, float iso) {
#if MC_ASYMPTOTIC_DECIDER
    if (mc_ambiguous_faces(case_index) != 0u) {
        float corners[8];
        for (uint c = 0u; c < 8u; ++c) {
            corners[c] = volume_texel(vol, ivec3(cell + mc_corner_offset(c)));
        }
        return mc_row_of_corners(corners, case_index, iso);
    }
#endif
    return mc_first_row(case_index);
}

// The samples the gradient at grid point p differences along `axis`: its neighbours inside,
// itself and one neighbour on the border. Returns the reciprocal of their distance (1 or 2
// samples), exact, so multiplying by it rounds as the CPU's division does, where Vulkan lets
// `/` be inexact.
float mc_gradient_ends(uvec3 p, uint axis, uvec3 dims, out uvec3 lo, out uvec3 hi) {
    lo = p;
    hi = p;
    lo[axis] = p[axis] > 0u ? p[axis] - 1u : 0u;
    hi[axis] = min(p[axis] + 1u, dims[axis] - 1u);
    return hi[axis] - lo[axis] == 2u ? 0.5 : 1.0;
}

// Gradient at grid point p: central differences inside, one-sided on the border.
vec3 mc_grid_gradient(VOLUME_SAMPLER vol, uvec3 p, uvec3 dims) {
    vec3 g;
    for (uint axis = 0u; axis < 3u; ++axis) {
        uvec3 lo;
        uvec3 hi;
        float inverse_span = mc_gradient_ends(p, axis, dims, lo, hi);
        g[axis] = (volume_texel(vol, ivec3(hi)) - volume_texel(vol, ivec3(lo))) * inverse_span;
    }
    return g;
}

// The vertex where the edge from grid point pa (sample a, gradient ga) to pb (b, gb) crosses
// iso, with its normal pointing toward lower values like the triangles (the gradient blended
// along the edge and negated; the edge direction pointing from the above end to the below end
// where the gradient vanishes).
void mc_edge_vertex_of(uvec3 pa, uvec3 pb, float a, float b, vec3 ga, vec3 gb, float iso,
                       out vec3 position, out vec3 normal) {
    float t = clamp((iso - a) / (b - a), 0.0, 1.0);
    if (isnan(t)) {
        t = 0.5;
    }
    vec3 dir = vec3(pb - pa);
    position = vec3(pa) + dir * t;
    vec3 g = ga * (1.0 - t) + gb * t;
    normal = dot(g, g) > 0.0 ? normalize(-g) : (a < iso ? -dir : dir);
}

// mc_edge_vertex_of for edge `edge` of `cell`, in grid coordinates, its samples read from `vol`.
void mc_edge_vertex(VOLUME_SAMPLER vol, uvec3 cell, uint edge, float iso, uvec3 dims,
                    out vec3 position, out vec3 normal) {
    uint corners = MC_EDGE_CORNERS[edge];
    uvec3 pa = cell + mc_corner_offset(corners & 15u);
    uvec3 pb = cell + mc_corner_offset(corners >> 4);
    mc_edge_vertex_of(pa, pb, volume_texel(vol, ivec3(pa)), volume_texel(vol, ivec3(pb)),
                      mc_grid_gradient(vol, pa, dims), mc_grid_gradient(vol, pb, dims), iso,
                      position, normal);
}
