#version 460
// Indirect dispatch arguments of one list: one workgroup per `per_group` stored patches (the
// count clamped to the list's capacity), on a 2-D grid where one row would exceed the device's
// limit; the passes flatten it again (param_group_index). A list too short to give the pass
// `spread_target` workgroups gets several along z per patch (at most PARAM_MAX_SPREAD), which
// share its work.
#define PARAM_STATE_BINDING 0
#include "param/patch.glsl"

layout(local_size_x = 1) in;

layout(push_constant) uniform PrepareParams {
    uvec2 max_groups;  // the device's limits on workgroups along x and y
    uint entry;        // which list
    uint capacity;     // patches the list holds
    uint per_group;    // patches per workgroup of the pass
    uint spread_target;  // workgroups wanted at least (0: one per patch)
} params;

void main() {
    uint n = min(entries[params.entry].count, params.capacity);
    uint groups = n / params.per_group + (n % params.per_group != 0u ? 1u : 0u);
    uint x = min(groups, params.max_groups.x);
    uint y = x == 0u ? 1u : groups / x + (groups % x != 0u ? 1u : 0u);
    entries[params.entry].x = x;
    entries[params.entry].y = min(y, params.max_groups.y);
    uint spread = 1u;
    if (params.spread_target > 0u && groups > 0u) {
        spread = clamp(params.spread_target / groups, 1u, PARAM_MAX_SPREAD);
    }
    entries[params.entry].z = spread;
}
