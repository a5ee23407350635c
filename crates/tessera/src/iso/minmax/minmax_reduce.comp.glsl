#version 460
// One octree level from the one below: each node takes the min of mins and max of maxes of its
// (up to) 2×2×2 children.

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 0) buffer Nodes { vec2 minmax_nodes[]; };

layout(push_constant) uniform ReduceParams {
    uvec4 child;   // xyz nodes per axis, w = index of the level's first node
    uvec4 parent;
} params;

void main() {
    uvec3 node = gl_GlobalInvocationID;
    if (any(greaterThanEqual(node, params.parent.xyz))) {
        return;
    }
    vec2 range = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));
    for (uint c = 0; c < 8; ++c) {
        uvec3 p = node * 2u + uvec3(c & 1u, (c >> 1) & 1u, c >> 2);
        if (all(lessThan(p, params.child.xyz))) {
            vec2 r = minmax_nodes[params.child.w + p.x + params.child.x * (p.y + params.child.y * p.z)];
            range = vec2(min(range.x, r.x), max(range.y, r.y));
        }
    }
    minmax_nodes[params.parent.w + node.x + params.parent.x * (node.y + params.parent.y * node.z)] = range;
}
