// Exclusive prefix sums over the invocations of one workgroup of MESHLET_WORKGROUP, shared by
// the region analysis and the extraction. Needs iso/meshlets/buffers.glsl (the counters, for
// reporting a subgroup layout the numbering cannot follow).

// meshlet_scan_counts(own, totals): the exclusive prefixes over the workgroup's invocations
// (in invocation order) of each one's three `own` counts, and their totals. Call from uniform
// control flow; the shared memory it uses is free again when it returns.
#if MESHLET_SUBGROUP_SCAN
// Each subgroup's sums; a subgroup has at least one invocation.
shared uvec3 s_subgroup_sums[MESHLET_WORKGROUP];

// Subgroup scans, then each invocation adds the sums of the subgroups before its own: two
// barriers instead of the shared-memory scan's 2 log2(MESHLET_WORKGROUP).
uvec3 meshlet_scan_counts(uvec3 own, out uvec3 totals) {
    // The order is the invocations' only where subgroups hold consecutive invocations, as
    // every driver lays out a one-dimensional workgroup; anything else is reported rather
    // than numbered otherwise than the CPU reference.
    if (gl_LocalInvocationIndex != gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID) {
        atomicOr(counters.overflow, MESHLET_OVERFLOW_MISMATCH);
    }
    uvec3 below = subgroupExclusiveAdd(own);
    uvec3 sum = subgroupAdd(own);
    if (subgroupElect()) {
        s_subgroup_sums[gl_SubgroupID] = sum;
    }
    barrier();
    totals = uvec3(0u);
    for (uint g = 0u; g < gl_NumSubgroups; ++g) {
        uvec3 sums = s_subgroup_sums[g];
        below += g < gl_SubgroupID ? sums : uvec3(0u);
        totals += sums;
    }
    barrier();
    return below;
}
#else
shared uvec3 s_scanned[MESHLET_WORKGROUP];

// A Hillis-Steele scan in shared memory: log2(MESHLET_WORKGROUP) rounds, each invocation
// adding the entry an offset below its own; no subgroup operations.
uvec3 meshlet_scan_counts(uvec3 own, out uvec3 totals) {
    uint me = gl_LocalInvocationIndex;
    uvec3 inclusive = own;
    s_scanned[me] = own;
    barrier();
    for (uint offset = 1u; offset < MESHLET_WORKGROUP; offset *= 2u) {
        uvec3 below = me >= offset ? s_scanned[me - offset] : uvec3(0u);
        barrier();
        inclusive += below;
        s_scanned[me] = inclusive;
        barrier();
    }
    totals = s_scanned[MESHLET_WORKGROUP - 1u];
    barrier();
    return inclusive - own;
}
#endif
