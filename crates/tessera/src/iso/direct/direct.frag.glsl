#version 460
// Shades the rasterized isosurface exactly as the ray marcher shades its hits.
#include "common/shading.glsl"

layout(location = 0) in vec3 normal_world;
layout(location = 1) in vec3 position_world;
layout(location = 0) out vec4 colour;

#include "iso/direct/params.glsl"

void main() {
    vec3 view = normalize(params.eye_world.xyz - position_world);
    vec3 n = dot(normal_world, normal_world) > 0.0 ? normalize(normal_world) : view;
    colour = vec4(gooch(n, params.light.xyz, view), 1.0);
}
