#version 460
// Shell traversal's compute path: one invocation per pixel traverses the pixel's ray (pixel
// model and near plane as tessera_data::tet::optical) and composites emission–absorption
// front to back over the background, stopping at the early-termination opacity.
layout(local_size_x = 8, local_size_y = 8) in;

#include "tet/shell/buffers.glsl"
#include "tet/shell/params.glsl"
layout(binding = 6) writeonly buffer Pixels { uint pixels[]; };  // packed RGBA8

#include "tet/table.glsl"
#include "tet/shell/integrate.glsl"
#include "tet/shell/ray_space.glsl"
#include "tet/shell/bvh.glsl"
#include "tet/shell/layout.glsl"
#include "tet/shell/traverse.glsl"
#include "tet/shell/stats.glsl"

FrontToBack sum;

bool visit_step(uint segment, ShellStep step) {
    add_stretch(sum, step.s_enter, step.s_exit, step.t_exit - step.t_enter);
    return !is_opaque(sum);
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.size))) {
        return;
    }
    vec2 size = vec2(params.size);
    float sx = (2.0 * (float(pixel.x) + 0.5) / size.x - 1.0) * params.tan_half_fov_x;
    float sy = (1.0 - 2.0 * (float(pixel.y) + 0.5) / size.y) * params.tan_half_fov_y;
    vec3 dir = normalize(params.forward + sx * params.right + sy * params.up);
    float t_min = params.near_depth / dot(dir, params.forward);
    sum = FrontToBack(vec3(0.0), vec3(1.0));
    add_counts(traverse(params.eye, dir, t_min, infinity()));
    vec3 light = sum.colour + sum.transmittance * params.background;
    pixels[pixel.y * params.size.x + pixel.x] = packUnorm4x8(vec4(light, 1.0));
}
