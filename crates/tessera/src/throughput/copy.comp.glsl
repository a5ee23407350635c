#version 460
// The memory system's rate for plain streaming: copies `words` 16-byte words from one storage
// buffer to another, each invocation striding through the whole range (so any grid covers it,
// and every load and store is 16 bytes wide and coalesced).
layout(local_size_x = 256) in;
layout(binding = 0) readonly buffer Source { uvec4 source[]; };
layout(binding = 1) writeonly buffer Destination { uvec4 destination[]; };
layout(push_constant) uniform CopyParams {
    uint words;
} params;

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < params.words; i += stride) {
        destination[i] = source[i];
    }
}
