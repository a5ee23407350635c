// One corner of a stored surface's triangle (meshlets, PMB blocks), from its grid-space
// position and normal to what every draw of them needs: the clip position and the world-space
// shading attributes. Needs iso/meshlet_draw/params.glsl and common/grid_world.glsl.

struct SurfaceCorner {
    vec4 clip;
    vec3 normal_world;
    vec3 position_world;
};

SurfaceCorner surface_corner(vec3 p, vec3 n) {
    vec3 grid_to_world = params.grid_to_world;
    return SurfaceCorner(params.grid_to_clip * vec4(p, 1.0), grid_normal_to_world(n, grid_to_world),
                         grid_point_to_world(p, params.dims, grid_to_world));
}
