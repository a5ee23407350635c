#version 460
// Turns the triangle count into the raster pass's indirect dispatch arguments: one invocation
// per triangle in groups of `group_size`, laid out on a 2-D grid of workgroups when one row
// would exceed the device's limit (the raster pass flattens the grid again).

layout(local_size_x = 1) in;
layout(binding = 0) buffer Counts {
    uint triangle_count;
    uint dispatch_x;
    uint dispatch_y;
    uint dispatch_z;
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
    dispatch_x = x;
    dispatch_y = min(y, params.max_groups.y);
    dispatch_z = 1u;
}
