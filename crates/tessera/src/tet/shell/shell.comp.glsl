#version 460
// Shell traversal's compute path: one invocation per pixel traverses the pixel's ray (pixel
// model and near plane as tessera_data::tet::optical) and composites emission–absorption
// front to back over the background, stopping at the early-termination opacity. With
// SHELL_EFFECTS each stretch's emission is scaled by its tet's lighting (effects.glsl), and
// with shadows the ray ends at the ground plane, whose colour lighting.comp.glsl left behind.
#include "tet/shell/stage.glsl"
#if !SHELL_RAY_TRACING
layout(local_size_x = 8, local_size_y = 8) in;
#endif

#include "tet/shell/buffers.glsl"
#include "tet/shell/params.glsl"
layout(binding = 6) writeonly buffer Pixels { uint pixels[]; };  // packed RGBA8
// The light reaching the eye per pixel before it is clamped and packed: 3 floats per pixel.
layout(binding = 7) writeonly buffer Radiance { float radiance[]; };

#include "tet/table.glsl"
#include "tet/shell/integrate.glsl"
#include "tet/shell/ray_space.glsl"
#include "tet/shell/hit.glsl"
#include "tet/shell/trace.glsl"
#include "tet/shell/layout.glsl"
#include "tet/shell/traverse.glsl"
#include "tet/shell/stats.glsl"
#include "tet/shell/pixel_ray.glsl"
#if SHELL_EFFECTS
#include "common/shading.glsl"
#include "tet/shell/effects.glsl"
#endif

FrontToBack sum;
vec3 ray_dir;

bool visit_step(uint segment, ShellStep step) {
    float len = step.t_exit - step.t_enter;
#if SHELL_EFFECTS
    vec3 midpoint = params.eye + ray_dir * (0.5 * (step.t_enter + step.t_exit));
    vec3 mean_absorption = table_mean_at(ABSORPTION_TABLE, step.s_enter, step.s_exit);
    vec3 light = shade_stretch(step.tet, midpoint, ray_dir, mean_absorption);
    add_lit_stretch(sum, step.s_enter, step.s_exit, len, light);
#else
    add_stretch(sum, step.s_enter, step.s_exit, len);
#endif
    return !is_opaque(sum);
}

void main() {
    uvec2 pixel = INVOCATION_ID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    uint index = pixel.y * params.size.x + pixel.x;
    vec4 ray = pixel_ray(pixel);
    ray_dir = ray.xyz;
    vec3 behind = params.background;
    float t_max = infinity();
#if SHELL_EFFECTS
#if SHELL_SHADOWS
    behind = ground_hits[index].rgb;
    t_max = ground_hits[index].w;
#endif
#endif
    sum = FrontToBack(vec3(0.0), vec3(1.0));
    add_counts(traverse(params.eye, ray_dir, ray.w, t_max));
    vec3 light = sum.colour + sum.transmittance * behind;
    radiance[3u * index] = light.r;
    radiance[3u * index + 1u] = light.g;
    radiance[3u * index + 2u] = light.b;
    pixels[index] = packUnorm4x8(vec4(light, 1.0));
}
