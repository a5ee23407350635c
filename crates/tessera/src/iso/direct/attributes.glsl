// Shading attributes of a compute-path triangle, stored beside the rasterizer's list under the
// same index: world-space normals and positions of its three corners (std430: 96 bytes).
// normal_world[0].w holds the id of what made the triangle (direct: the block's linear id; the
// meshlet draw: the meshlet's), as
// uintBitsToFloat(id) (read it back with floatBitsToUint; loads and stores keep the bits).
struct TriangleAttributes {
    vec4 normal_world[3];
    vec4 position_world[3];
};
