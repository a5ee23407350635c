#version 460
// Shades the rasterized isosurface exactly as the ray marcher shades its hits.
#if MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#include "common/shading.glsl"

layout(location = 0) in vec3 normal_world;
layout(location = 1) in vec3 position_world;
layout(location = 0) out vec4 colour;

#include "iso/direct/params.glsl"
#include "iso/direct/views.glsl"

void main() {
    colour = vec4(shade_surface(normal_world, position_world, view_eye_world(), params.light.xyz), 1.0);
}
