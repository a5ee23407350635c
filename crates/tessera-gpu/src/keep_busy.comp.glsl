#version 460
// Integer arithmetic with almost no memory traffic, run after a timed benchmark frame so that
// the GPU stays loaded while the host reads that frame's timestamps and records the next one.
// Each invocation steps a linear congruential generator `iterations` times from its own seed;
// the first invocation of each workgroup stores its result, which keeps the loop alive and
// lets a test check that the dispatch ran (keep_busy.rs computes the same numbers and defines
// WORKGROUP_SIZE and the generator's GENERATOR_MULTIPLIER and GENERATOR_INCREMENT).

layout(local_size_x = WORKGROUP_SIZE) in;

layout(binding = 0, std430) writeonly buffer Sink {
    uint last_state[];  // one per workgroup
} sink;

layout(push_constant) uniform KeepBusyParams {
    uint iterations;
    uint seed;
} params;

void main() {
    uint state = params.seed ^ gl_GlobalInvocationID.x;
    for (uint i = 0u; i < params.iterations; ++i) {
        state = state * GENERATOR_MULTIPLIER + GENERATOR_INCREMENT;
    }
    if (gl_LocalInvocationID.x == 0u) {
        sink.last_state[gl_WorkGroupID.x] = state;
    }
}
