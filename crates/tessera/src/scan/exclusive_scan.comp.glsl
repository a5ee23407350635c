#version 460
// Exclusive prefix sum of the first `count` words of a buffer, in place, by one workgroup: each
// invocation sums a run of consecutive words, a scan of the runs' sums over the workgroup
// (common/workgroup_scan.glsl) gives each run its start, and each invocation writes its run's
// prefixes. Meant for counts of some hundred thousand words at most (e.g. one per screen
// tile), where one workgroup suffices.

layout(local_size_x = SCAN_WORKGROUP) in;

layout(binding = 0) buffer Values { uint values[]; };

layout(push_constant) uniform ScanParams {
    uint count;
} params;

#define WORKGROUP_SCAN_SIZE SCAN_WORKGROUP
#define WORKGROUP_SCAN_SUBGROUPS 0
#include "common/workgroup_scan.glsl"

void main() {
    uint i = gl_LocalInvocationIndex;
    uint run = (params.count + uint(SCAN_WORKGROUP) - 1u) / uint(SCAN_WORKGROUP);
    uint begin = min(i * run, params.count);
    uint end = min(begin + run, params.count);
    uint sum = 0u;
    uint k = begin;
    // Four loads in flight before their sum needs them: the run's words are read one by one,
    // so their latency, not bandwidth, bounds this loop.
    for (; k + 4u <= end; k += 4u) {
        uvec4 four = uvec4(values[k], values[k + 1u], values[k + 2u], values[k + 3u]);
        sum += four.x + four.y + four.z + four.w;
    }
    for (; k < end; ++k) {
        sum += values[k];
    }
    // Where each run starts: the prefix of the runs' sums (the scan's other counts unused).
    uvec3 totals;
    uint prefix = workgroup_exclusive_scan(uvec3(sum, 0u, 0u), totals).x;
    for (k = begin; k < end; ++k) {
        uint value = values[k];
        values[k] = prefix;
        prefix += value;
    }
}
