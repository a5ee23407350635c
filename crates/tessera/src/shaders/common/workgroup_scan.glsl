// Exclusive prefix sums of three counts over the invocations of a one-dimensional workgroup.
// The includer defines WORKGROUP_SCAN_SIZE (the workgroup's invocations) and
// WORKGROUP_SCAN_SUBGROUPS (1 to use subgroup arithmetic, which it must then enable; 0 for a
// shared-memory scan). No subgroup size is assumed.
//
// workgroup_exclusive_scan(own, totals): each invocation's exclusive prefix of `own` and the
// workgroup's totals. The prefixes partition the totals among the invocations; they follow
// the invocations' order where workgroup_scan_in_invocation_order() holds (always without
// subgroups; with them where subgroups are laid over consecutive invocations, as drivers lay
// out one-dimensional workgroups). Call from uniform control flow; the shared memory it uses
// is free again when it returns.

#if WORKGROUP_SCAN_SUBGROUPS
// Each subgroup's sums; a subgroup has at least one invocation.
shared uvec3 s_subgroup_sums[WORKGROUP_SCAN_SIZE];

bool workgroup_scan_in_invocation_order() {
    return gl_LocalInvocationIndex == gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID;
}

// Subgroup scans, then each invocation adds the sums of the subgroups before its own: two
// barriers instead of the shared-memory scan's 2 log2(WORKGROUP_SCAN_SIZE).
uvec3 workgroup_exclusive_scan(uvec3 own, out uvec3 totals) {
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
shared uvec3 s_scanned[WORKGROUP_SCAN_SIZE];

bool workgroup_scan_in_invocation_order() {
    return true;
}

// A Hillis-Steele scan in shared memory: ceil(log2(WORKGROUP_SCAN_SIZE)) rounds, each
// invocation adding the entry an offset below its own.
uvec3 workgroup_exclusive_scan(uvec3 own, out uvec3 totals) {
    uint me = gl_LocalInvocationIndex;
    uvec3 inclusive = own;
    s_scanned[me] = own;
    barrier();
    for (uint offset = 1u; offset < WORKGROUP_SCAN_SIZE; offset *= 2u) {
        uvec3 below = me >= offset ? s_scanned[me - offset] : uvec3(0u);
        barrier();
        inclusive += below;
        s_scanned[me] = inclusive;
        barrier();
    }
    totals = s_scanned[WORKGROUP_SCAN_SIZE - 1u];
    barrier();
    return inclusive - own;
}
#endif
