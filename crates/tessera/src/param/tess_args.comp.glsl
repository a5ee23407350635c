#version 460
// The draw's indirect arguments from the LOD stage's count of patches to render (clamped to the
// list's capacity): one vertex (a single-point patch) per patch, in instances of at most
// patches_per_instance vertices (param/tess.rs says why).
#define PARAM_STATE_BINDING 0
#include "param/patch.glsl"

layout(local_size_x = 1) in;
layout(binding = 1, std430) writeonly buffer DrawArgs { uint draw_args[4]; };

layout(push_constant) uniform TessArgsParams {
    uint render_capacity;
    uint patches_per_instance;
} params;

void main() {
    uint n = min(entries[0].count, params.render_capacity);
    uint per = params.patches_per_instance;
    draw_args[0] = min(n, per);
    draw_args[1] = n / per + (n % per != 0u ? 1u : 0u);
    draw_args[2] = 0u;
    draw_args[3] = 0u;
}
