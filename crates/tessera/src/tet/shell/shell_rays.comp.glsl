#version 460
// Shell traversal of given rays (shadow rays, and the per-ray checks against the CPU
// traversal): per ray, the emission–absorption sum and the tets visited in order, the first
// RECORDED_STEPS of them kept with their segment numbers.
#include "tet/shell/stage.glsl"
#if !SHELL_RAY_TRACING
layout(local_size_x = 64) in;
#endif

#include "tet/shell/buffers.glsl"
#include "tet/shell/params.glsl"
struct ShellRay {
    vec3 origin;
    float t_min;
    vec3 dir;
    float t_max;
};
layout(binding = 6) readonly buffer Rays { ShellRay rays[]; };
struct RayResult {
    vec3 colour;
    uint steps;        // tets reported (may exceed RECORDED_STEPS)
    vec3 transmittance;
    uint segments;
};
layout(binding = 7) writeonly buffer Results { RayResult results[]; };
struct VisitedTet {
    uint tet;
    uint segment;
};
layout(binding = 8) writeonly buffer Visited { VisitedTet visited[]; };

#include "tet/table.glsl"
#include "tet/shell/integrate.glsl"
#include "tet/shell/ray_space.glsl"
#include "tet/shell/hit.glsl"
#include "tet/shell/trace.glsl"
#include "tet/shell/layout.glsl"
#include "tet/shell/traverse.glsl"
#include "tet/shell/stats.glsl"

FrontToBack sum;
uint ray_index;
uint reported_steps;

bool visit_step(uint segment, ShellStep step) {
    if (reported_steps < uint(RECORDED_STEPS)) {
        uint slot = ray_index * uint(RECORDED_STEPS) + reported_steps;
        visited[slot].tet = step.tet;
        visited[slot].segment = segment;
    }
    reported_steps += 1u;
    add_stretch(sum, step.s_enter, step.s_exit, step.t_exit - step.t_enter);
    return !is_opaque(sum);
}

void main() {
    ray_index = INVOCATION_ID.x;
    if (ray_index >= params.size.x) {
        return;
    }
    sum = FrontToBack(vec3(0.0), vec3(1.0));
    reported_steps = 0u;
    // Fields one by one: a copy of the whole struct would give the shader a second type of
    // that name, which the layout check cannot tell from the buffer's.
    TraversalCounts counts = traverse(rays[ray_index].origin, rays[ray_index].dir, rays[ray_index].t_min,
                                      rays[ray_index].t_max);
    add_counts(counts);
    results[ray_index].colour = sum.colour;
    results[ray_index].steps = reported_steps;
    results[ray_index].transmittance = sum.transmittance;
    results[ray_index].segments = counts.segments;
}
