#version 460
// The effects' passes (tessera_data::tet::shell::lighting), LIGHTING_PASS picking one: per
// tet, its scalar gradient (PASS_GRADIENTS), its transmittance from the centre towards the
// light (PASS_SHADOWS) and its mean transmittance over the AO hemisphere (PASS_OCCLUSION);
// per pixel, the ground plane lit through the volume (PASS_GROUND). Secondary rays march by
// the same traversal as pixel rays and stop at the same opacity.
#include "tet/shell/stage.glsl"
#if !SHELL_RAY_TRACING
#if LIGHTING_PASS == PASS_GROUND
layout(local_size_x = 8, local_size_y = 8) in;
#else
layout(local_size_x = 64) in;
#endif
#endif

#include "tet/shell/buffers.glsl"
#include "tet/shell/params.glsl"
#include "tet/table.glsl"
#include "tet/shell/integrate.glsl"
#include "tet/shell/ray_space.glsl"
#include "tet/shell/hit.glsl"
#include "tet/shell/trace.glsl"
#include "tet/shell/layout.glsl"
#include "tet/shell/traverse.glsl"
#include "tet/shell/stats.glsl"
#include "tet/shell/pixel_ray.glsl"
#include "common/shading.glsl"
#include "tet/shell/effects.glsl"

FrontToBack sum;
TraversalCounts secondary_counts = TraversalCounts(0u, 0u, 0u, 0u, 0u, 0u);
uint secondary_rays = 0u;

bool visit_step(uint segment, ShellStep step) {
    add_stretch(sum, step.s_enter, step.s_exit, step.t_exit - step.t_enter);
    return !is_opaque(sum);
}

// The transmittance along origin + t dir for 0 ≤ t ≤ t_max.
vec3 secondary(vec3 origin, vec3 dir, float t_max) {
    sum = FrontToBack(vec3(0.0), vec3(1.0));
    TraversalCounts c = traverse(origin, dir, 0.0, t_max);
    secondary_rays += 1u;
    secondary_counts.steps += c.steps;
    secondary_counts.dead_ends += c.dead_ends;
    secondary_counts.step_limits += c.step_limits;
    return sum.transmittance;
}

vec3 towards_light_from(vec3 p) {
    vec4 l = towards_light(p);
    return secondary(p, l.xyz, l.w);
}

void main() {
#if LIGHTING_PASS == PASS_GROUND
    uvec2 pixel = INVOCATION_ID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    vec4 ray = pixel_ray(pixel);
    float t = ground_hit(params.eye, ray.xyz, ray.w);
    vec4 hit = vec4(params.background, infinity());
    if (!isinf(t)) {
        vec3 p = params.eye + ray.xyz * t;
        hit = vec4(ground_colour(towards_light(p).xyz, towards_light_from(p)), t);
    }
    ground_hits[pixel.y * params.size.x + pixel.x] = hit;
    add_secondary_counts(STAT_SHADOW_RAYS, secondary_rays, secondary_counts);
#else
    uint tet = INVOCATION_ID.x;
    if (tet >= params.tet_count) {
        return;
    }
    uvec4 ids = tet_vertices[tet];
    vec3 corner[4] = vec3[4](vertices[ids.x].xyz, vertices[ids.y].xyz, vertices[ids.z].xyz, vertices[ids.w].xyz);
    vec3 centre = (corner[0] + corner[1] + corner[2] + corner[3]) * 0.25;
#if LIGHTING_PASS == PASS_GRADIENTS
    // s(p) = s0 + rise · B (p − corner 0), B the barycentric map: ∇s = Bᵀ rise.
    vec4 s = vec4(normalized_scalar(vertices[ids.x].w), normalized_scalar(vertices[ids.y].w),
                  normalized_scalar(vertices[ids.z].w), normalized_scalar(vertices[ids.w].w));
    mat3 edges = mat3(corner[1] - corner[0], corner[2] - corner[0], corner[3] - corner[0]);
    vec3 gradient = vec3(0.0);
    if (determinant(edges) != 0.0) {
        gradient = transpose(inverse(edges)) * (s.yzw - s.x);
    }
    bool finite = !any(isinf(gradient)) && !any(isnan(gradient));
    gradients[tet] = vec4(finite ? gradient : vec3(0.0), 0.0);
#elif LIGHTING_PASS == PASS_SHADOWS
    tet_light[tet] = vec4(towards_light_from(centre), 0.0);
    add_secondary_counts(STAT_SHADOW_RAYS, secondary_rays, secondary_counts);
#elif LIGHTING_PASS == PASS_OCCLUSION
    vec3 n = ao_normal(gradients[tet].xyz);
    vec3 u;
    vec3 v;
    hemisphere_frame(n, u, v);
    const vec3 pattern[SHELL_AO_SAMPLES] = AO_PATTERN;
    vec3 total = vec3(0.0);
    for (uint i = 0u; i < uint(SHELL_AO_SAMPLES); ++i) {
        vec3 dir = u * pattern[i].x + v * pattern[i].y + n * pattern[i].z;
        total += secondary(centre, dir, effect.ao_radius);
    }
    occlusion[tet] = vec4(total / float(SHELL_AO_SAMPLES), 0.0);
    add_secondary_counts(STAT_AO_RAYS, secondary_rays, secondary_counts);
#endif
#endif
}
