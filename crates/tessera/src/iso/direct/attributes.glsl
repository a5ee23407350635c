// Shading attributes of a compute-path triangle, stored beside the rasterizer's list under the
// same index: world-space normals of its three corners (std430: 48 bytes). Positions are not
// stored: the resolve takes them from the rasterizer's clip-space corners (its clip_to_world),
// which halves what a list holds per triangle and lets a list twice as long fit a storage buffer.
// normal_world[0].w holds the id of what made the triangle (direct: the block's linear id; the
// meshlet draw: the meshlet's), as
// uintBitsToFloat(id) (read it back with floatBitsToUint; loads and stores keep the bits).
struct TriangleAttributes {
    vec4 normal_world[3];
};
