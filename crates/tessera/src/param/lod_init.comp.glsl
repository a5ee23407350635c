#version 460
// PATCH INITIALIZATION (paper E §4): per object its parameter domain, whole or cut into
// pre_split × pre_split equal patches (tessera_data::param::Patch::pre_split: a power of two, so
// the cuts are exact in any IEEE arithmetic), into the list LOD step 0 evaluates.
#define PARAM_STATE_BINDING 3
#include "param/scene.glsl"
#include "param/patch.glsl"
#include "param/lod_params.glsl"
#include "common/indirect_args.glsl"

layout(local_size_x = 64) in;
layout(binding = 4, std430) writeonly buffer PatchesOut { Patch patches_out[]; };

float cut(vec2 range, uint i, uint k) {
    if (i == 0u) {
        return range.x;
    }
    if (i == k) {
        return range.y;
    }
    precise float t = float(i) * (1.0 / float(k));
    precise float at = range.x + (range.y - range.x) * t;
    return at;
}

void main() {
    // Workgroups spread over x and y past the device's row limit.
    uint index = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u
                 + gl_LocalInvocationIndex;
    uint k = params.pre_split;
    uint per_object = k * k;
    uint count = params.object_count * per_object;
    if (index == 0u) {
        entries[1].count = count;
        uint stored = min(count, params.eval_capacity);
        if (stored > 0u) {
            GROW_INDIRECT_ARGS(entries[1].x, entries[1].y, entries[1].z, stored, 1u);
        }
        if (count > params.eval_capacity) {
            dropped = count - params.eval_capacity;  // the frame is refused
        }
    }
    if (index >= count || index >= params.eval_capacity) {
        return;
    }
    uint object = index / per_object;
    uint cell = index % per_object;
    uint i = cell % k;
    uint j = cell / k;
    vec4 d = param_objects[object].domain;
    vec2 u = vec2(cut(d.xy, i, k), cut(d.xy, i + 1u, k));
    vec2 v = vec2(cut(d.zw, j, k), cut(d.zw, j + 1u, k));
    patches_out[index] = Patch(u, v, vec2(0.0), object, 0u);
}
