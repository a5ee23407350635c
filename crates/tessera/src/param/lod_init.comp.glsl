#version 460
// PATCH INITIALIZATION (paper E §4): one patch per object, its whole parameter domain, into the
// list LOD step 0 evaluates.
#define PARAM_STATE_BINDING 3
#include "param/scene.glsl"
#include "param/patch.glsl"
#include "param/lod_params.glsl"

layout(local_size_x = 64) in;
layout(binding = 4, std430) writeonly buffer PatchesOut { Patch patches_out[]; };

void main() {
    uint object = gl_GlobalInvocationID.x;
    if (object == 0u) {
        entries[1].count = params.object_count;
        if (params.object_count > params.eval_capacity) {
            dropped = params.object_count - params.eval_capacity;  // the frame is refused
        }
    }
    if (object >= params.object_count || object >= params.eval_capacity) {
        return;
    }
    vec4 d = param_objects[object].domain;
    patches_out[object] = Patch(d.xy, d.zw, vec2(0.0), object, 0u);
}
