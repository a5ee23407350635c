// Shading attributes of a compute-path triangle, stored beside the rasterizer's list under the
// same index: world-space normals and positions of its three corners (std430: 96 bytes).
struct TriangleAttributes {
    vec4 normal_world[3];
    vec4 position_world[3];
};
