// Shading attributes of a compute-path triangle, stored beside the rasterizer's list under the
// same index (std430: 16 bytes; TriangleAttributes in compute.rs). Positions are not stored:
// the resolve takes them from the rasterizer's clip-space corners (its clip_to_world). The
// normals are packed (common/unit_vector.glsl): the extraction writes and the resolve reads a
// third of what three vec4s took, on paths whose cost is per triangle and per pixel.
// Needs common/unit_vector.glsl.
struct TriangleAttributes {
    uint corner_normals[3];  // world-space unit normals, pack_unit_vector
    uint maker;              // direct: the block's linear id; the meshlet draw: the meshlet's
};
