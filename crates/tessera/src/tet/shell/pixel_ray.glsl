// The ray of pixel `pixel` as tessera_data::tet::optical casts it: unit direction from the eye,
// and in w the distance along it to the near plane.
// Needs params.glsl.

vec4 pixel_ray(uvec2 pixel) {
    vec2 size = vec2(params.size);
    float sx = (2.0 * (float(pixel.x) + 0.5) / size.x - 1.0) * params.tan_half_fov_x;
    float sy = (1.0 - 2.0 * (float(pixel.y) + 0.5) / size.y) * params.tan_half_fov_y;
    vec3 dir = normalize(params.forward + sx * params.right + sy * params.up);
    return vec4(dir, params.near_depth / dot(dir, params.forward));
}
