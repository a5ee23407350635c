// Shading attributes of a compute-path triangle, stored beside the rasterizer's list under the
// same index (std430: 48 bytes; TriangleAttributes in compute.rs). Positions are not stored:
// the resolve takes them from the rasterizer's clip-space corners (its clip_to_world).
// std430 gives each corner's vec3 a 16-byte slot; its last word carries the id of what made
// the triangle (direct: the block's linear id; the meshlet draw: the meshlet's), the same in
// all three, so that each writer stores a corner as one 16-byte write. Normals packed into 16
// bytes a triangle measured slower (docs/BENCHMARKS.md, run 117).
struct CornerAttributes {
    vec3 normal_world;
    uint maker;
};

struct TriangleAttributes {
    CornerAttributes corners[3];
};
