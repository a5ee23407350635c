// Push constants of the meshlet extraction passes (host side: MeshletParams).
layout(push_constant) uniform MeshletParams {
    uvec3 volume_dims;      // samples per axis
    float isovalue;
    uvec3 block_dims;       // blocks per axis: level 0 of the min-max octree
    // What the output buffers hold; a block whose reservation passes any of them writes
    // nothing and sets MESHLET_OVERFLOW_CAPACITY.
    uint meshlet_capacity;
    uint vertex_capacity;
    uint triangle_capacity;
} params;
