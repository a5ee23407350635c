#version 460
// Turns the triangle count into the raster pass's indirect dispatch arguments: one invocation
// per triangle in groups of `group_size`, laid out on a 2-D grid of workgroups when one row
// would exceed the device's limit (the raster pass flattens the grid again).

layout(local_size_x = 1) in;
layout(binding = 0) buffer Counts {
    uint triangle_count;
    uint dispatch[3];
};

layout(push_constant) uniform PrepareParams {
    uvec2 max_groups;  // the device's limits on workgroups along x and y
    uint group_size;   // invocations per workgroup of the raster pass
} params;

void main() {
    uint n = triangle_count;
    uint groups = n / params.group_size + (n % params.group_size != 0u ? 1u : 0u);
    uint x = min(groups, params.max_groups.x);
    uint y = x == 0u ? 1u : groups / x + (groups % x != 0u ? 1u : 0u);
    dispatch = uint[3](x, min(y, params.max_groups.y), 1u);
}
