// Frustum culling of a box of grid space, shared by the draws of stored surfaces (meshlets,
// PMB blocks).

// Whether the box [lo, hi] (grid units) may reach the view of `grid_to_clip`: false only when
// its eight corners all lie beyond one clip plane, so no triangle inside the box is culled
// that the rasterizer would draw.
bool box_in_frustum(mat4 grid_to_clip, vec3 lo, vec3 hi) {
    uint outside_all = 63u;
    for (uint c = 0u; c < 8u; ++c) {
        vec3 corner = mix(lo, hi, vec3(uvec3(c, c >> 1u, c >> 2u) & 1u));
        vec4 clip = grid_to_clip * vec4(corner, 1.0);
        uint outside = (clip.x < -clip.w ? 1u : 0u) | (clip.x > clip.w ? 2u : 0u)
                     | (clip.y < -clip.w ? 4u : 0u) | (clip.y > clip.w ? 8u : 0u)
                     | (clip.z < 0.0 ? 16u : 0u) | (clip.z > clip.w ? 32u : 0u);
        outside_all &= outside;
    }
    return outside_all == 0u;
}
