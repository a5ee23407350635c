#version 460
// Bookkeeping between culling passes, one invocation: mode 0 resets the lists of a frame
// (counts to zero, indirect y/z to one); mode 1 turns the occupied-region count into the
// proxy-quad draw's workgroup count.
layout(local_size_x = 1) in;
layout(binding = 0) buffer Occupied { uint quad_groups[3]; uint occupied_count; uint occupied[]; };
layout(binding = 1) buffer NewBlocks { uint new_args[3]; uint new_pad; uint new_blocks[]; };
layout(binding = 2) buffer NextBlocks { uint next_args[3]; uint next_pad; uint next_blocks[]; };
layout(push_constant) uniform SetupParams { uint mode; } setup;

const uint QUADS_PER_WORKGROUP = 32u;

void main() {
    if (setup.mode == 0u) {
        quad_groups = uint[3](0u, 1u, 1u);
        occupied_count = 0u;
        new_args = uint[3](0u, 1u, 1u);
        next_args = uint[3](0u, 1u, 1u);
    } else {
        // Spread over x and y so no axis passes the 65,535 every device accepts.
        uint groups = max((occupied_count + QUADS_PER_WORKGROUP - 1u) / QUADS_PER_WORKGROUP, 1u);
        quad_groups[0] = min(groups, 65535u);
        quad_groups[1] = (groups + quad_groups[0] - 1u) / quad_groups[0];
    }
}
