#version 460
// Three octree levels above `child_level` in one pass, each node the min of mins and max of
// maxes of its (up to) 2×2×2 children: a workgroup takes 8×8×8 nodes of the child level,
// each invocation 2×2×2 of them (one node of the level above, reduced in registers), then
// the workgroup's 4×4×4 and 2×2×2 of those in shared memory. A pass per level left a dispatch
// and a barrier per level, the build's fixed cost on volumes of a few hundred MB.

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 0) buffer Nodes { vec2 minmax_nodes[]; };
// Per level: nodes per axis, and in w the index of its first node.
layout(binding = 1) readonly buffer Levels { uvec4 levels[]; };

layout(push_constant) uniform LevelsParams {
    uint child_level;  // the level read; levels child_level + 1 ..= + 3 are written
    uint level_count;
} params;

shared vec2 s_range[64];

const vec2 EMPTY_RANGE = vec2(uintBitsToFloat(0x7f800000u), uintBitsToFloat(0xff800000u));

vec2 merge(vec2 a, vec2 b) {
    return vec2(min(a.x, b.x), max(a.y, b.y));
}

uvec3 corner(uint c) {
    return uvec3(c & 1u, (c >> 1) & 1u, c >> 2);
}

uint local_slot(uvec3 p) {
    return p.x + 4u * (p.y + 4u * p.z);
}

// Writes node `p` of `level` where the octree has that level and node.
void store(uint level, uvec3 p, vec2 range) {
    if (level < params.level_count && all(lessThan(p, levels[level].xyz))) {
        uvec4 l = levels[level];
        minmax_nodes[l.w + p.x + l.x * (p.y + l.y * p.z)] = range;
    }
}

void main() {
    uvec3 me = gl_LocalInvocationID;
    uvec4 child = levels[params.child_level];
    // One node of the level above, from its children in the child level.
    uvec3 parent = gl_WorkGroupID * 4u + me;
    vec2 range = EMPTY_RANGE;
    for (uint c = 0u; c < 8u; ++c) {
        uvec3 p = parent * 2u + corner(c);
        if (all(lessThan(p, child.xyz))) {
            range = merge(range, minmax_nodes[child.w + p.x + child.x * (p.y + child.y * p.z)]);
        }
    }
    store(params.child_level + 1u, parent, range);
    // Missing nodes hold the empty range, which merging ignores.
    s_range[local_slot(me)] = range;
    barrier();
    bool second = all(lessThan(me, uvec3(2u)));
    if (second) {
        range = EMPTY_RANGE;
        for (uint c = 0u; c < 8u; ++c) {
            range = merge(range, s_range[local_slot(me * 2u + corner(c))]);
        }
        store(params.child_level + 2u, gl_WorkGroupID * 2u + me, range);
    }
    barrier();
    if (second) {
        s_range[local_slot(me)] = range;
    }
    barrier();
    if (all(equal(me, uvec3(0u)))) {
        range = EMPTY_RANGE;
        for (uint c = 0u; c < 8u; ++c) {
            range = merge(range, s_range[local_slot(corner(c))]);
        }
        store(params.child_level + 3u, gl_WorkGroupID, range);
    }
}
