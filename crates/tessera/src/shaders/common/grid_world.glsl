// From a volume's grid (sample-index units) to world space, where the volume is centred at the
// origin and `grid_to_world` gives world units per grid unit along each axis: the one place
// every isosurface path turns its grid-space vertices into shading attributes.

vec3 grid_point_to_world(vec3 p, uvec3 dims, vec3 grid_to_world) {
    return (p - 0.5 * vec3(dims - 1u)) * grid_to_world;
}

// Normals transform by the inverse of the (diagonal) scale; a zero gradient stays zero.
vec3 grid_normal_to_world(vec3 n, vec3 grid_to_world) {
    vec3 nw = n / grid_to_world;
    return dot(nw, nw) > 0.0 ? normalize(nw) : nw;
}
