// The vertex on a grid edge exactly as tessera_data::marching_cubes::edge_vertex places it,
// for extractors held to the CPU bit for bit (the meshlet paths). Needs common/volume.glsl,
// common/exact.glsl and common/mc_cell.glsl. The same operations in the same order, `precise`
// so nothing is fused, and division and square root rounded as the CPU rounds them.

// The vertex where the edge from sample `start` one step along `axis` crosses iso, in grid
// coordinates, and its normal (the negated gradient blended along the edge, normalized; where
// it vanishes, the edge direction from its above end to its below end), from the values `a`
// at the start and `b` at the end and the gradients there.
void mc_exact_vertex(uvec3 start, uint axis, float a, float b, vec3 ga, vec3 gb, float iso,
                     out vec3 position, out vec3 normal) {
    precise float rise = iso - a;
    precise float run = b - a;
    float t = rounded_divide(rise, run);
    t = isnan(t) ? 0.5 : clamp(t, 0.0, 1.0);
    position = vec3(start);
    precise float along = position[axis] + t;
    position[axis] = along;

    precise float keep = 1.0 - t;
    precise vec3 g = ga * keep + gb * t;
    precise vec3 n = -g;
    precise float length_squared = (n.x * n.x + n.y * n.y) + n.z * n.z;
    float inverse_length = rounded_divide(1.0, rounded_sqrt(length_squared));
    vec3 dir = vec3(0.0);
    dir[axis] = 1.0;
    bool usable = !isinf(inverse_length) && !isnan(inverse_length) && inverse_length > 0.0;
    precise vec3 unit = n * inverse_length;
    normal = usable ? unit : (a < iso ? -dir : dir);
}

// mc_exact_vertex with the values read from the volume.
void mc_exact_edge_vertex(VOLUME_SAMPLER vol, uvec3 start, uint axis, float iso, uvec3 dims,
                          out vec3 position, out vec3 normal) {
    uvec3 end = start;
    end[axis] += 1u;
    mc_exact_vertex(start, axis, volume_texel(vol, ivec3(start)), volume_texel(vol, ivec3(end)),
                    mc_grid_gradient(vol, start, dims), mc_grid_gradient(vol, end, dims), iso,
                    position, normal);
}
