#version 460
// Tessellation levels of one patch to render (param/tess.rs documents the rule). Four
// invocations, one per outer edge in Vulkan's quad order (u = 0, v = 0, u = 1, v = 1): with
// adaptive levels each measures its edge's screen length on 8 points, as an LOD line does, so
// that two patches sharing a whole edge pick the same level and leave no crack; the inner levels
// come from the LOD stage's extents (paper E §4.2).
#include "param/functions.glsl"
#include "param/view.glsl"
// patch.glsl also defines the compute passes' workgroup index, from built-ins this stage lacks;
// stand-ins let it compile (it is never called here).
#define gl_WorkGroupID uvec3(0u)
#define gl_NumWorkGroups uvec3(0u)
#define PARAM_STATE_BINDING 4
#include "param/patch.glsl"
#undef gl_WorkGroupID
#undef gl_NumWorkGroups
#include "param/tess_params.glsl"
#include "param/min_extent.glsl"

layout(vertices = 4) out;
layout(binding = 3, std430) readonly buffer PatchesRender { Patch patches_render[]; };

layout(location = 0) in uint v_patch[];
layout(location = 0) patch out vec4 tc_range;  // u0, u1, v0, v1
layout(location = 1) patch out uint tc_object;

const uint EDGE_POINTS = 8u;

// Parameter k of EDGE_POINTS along r, the ends exact.
float edge_param(vec2 r, uint k) {
    return k == 0u ? r.x : (k == EDGE_POINTS - 1u ? r.y : r.x + (r.y - r.x) * (float(k) / float(EDGE_POINTS - 1u)));
}

// Sum of the edge's segment lengths in pixels, ends clamped to the viewport, segments with an
// end behind the eye left out (the LOD stage's line measure). Depends only on the edge's own
// parameters, whichever patch asks.
float edge_length(Patch p, uint edge) {
    bool along_v = (edge & 1u) == 0u;
    float held = edge == 0u ? p.u.x : (edge == 1u ? p.v.x : (edge == 2u ? p.u.y : p.v.y));
    vec2 range = along_v ? p.v : p.u;
    float sum = 0.0;
    vec2 previous = vec2(0.0);
    bool previous_front = false;
    for (uint k = 0u; k < EDGE_POINTS; ++k) {
        float s = edge_param(range, k);
        vec2 uv = along_v ? vec2(held, s) : vec2(s, held);
        vec3 world = param_world_position(p.object, uv.x, uv.y);
        vec2 pixel;
        float depth;
        bool front = param_project(params.world_to_clip, params.viewport, world, pixel, depth) && !any(isnan(pixel));
        pixel = clamp(pixel, vec2(0.0), params.viewport);
        if (front && previous_front) {
            sum += length(pixel - previous);
        }
        previous = pixel;
        previous_front = front;
    }
    return sum;
}

float adaptive_level(float pixels) {
    return clamp(ceil(pixels / params.pixels_per_segment), params.min_level, params.max_level);
}

void main() {
    uint index = v_patch[0];
    uint edge = uint(gl_InvocationID);
    if (index >= min(entries[0].count, params.render_capacity)) {
        gl_TessLevelOuter[edge] = 0.0;  // the last instance's unused slots: no patch
        return;
    }
    Patch p = patches_render[index];
    bool fixed_levels = params.fixed_level > 0.0;
    // Edges 0 and 2 run along v, 1 and 3 along u; a patch's neighbour across a whole edge has
    // the same range along it, so both pick the same floor.
    vec2 least = param_min_extent(p, params.world_to_clip, params.viewport);
    float edge_least = (edge & 1u) == 0u ? least.y : least.x;
    gl_TessLevelOuter[edge] = fixed_levels ? params.fixed_level : adaptive_level(max(edge_length(p, edge), edge_least));
    if (edge == 0u) {
        gl_TessLevelInner[0] = fixed_levels ? params.fixed_level : adaptive_level(max(p.extent.x, least.x));
        gl_TessLevelInner[1] = fixed_levels ? params.fixed_level : adaptive_level(max(p.extent.y, least.y));
        tc_range = vec4(p.u, p.v);
        tc_object = p.object;
    }
}
