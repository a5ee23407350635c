// The meshlet extraction's prefix sums over its workgroup (common/workgroup_scan.glsl), in
// invocation order as the CPU reference numbers vertices; a subgroup layout that order
// cannot follow is reported rather than numbered otherwise. Needs
// iso/meshlets/{params,buffers}.glsl.
#define WORKGROUP_SCAN_SIZE MESHLET_WORKGROUP
#define WORKGROUP_SCAN_SUBGROUPS MESHLET_SUBGROUP_SCAN
#include "common/workgroup_scan.glsl"

uvec3 meshlet_scan_counts(uvec3 own, out uvec3 totals) {
    if (!workgroup_scan_in_invocation_order()) {
        atomicOr(counters.overflow, MESHLET_OVERFLOW_MISMATCH);
    }
    return workgroup_exclusive_scan(own, totals);
}
