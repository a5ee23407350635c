#version 460
// Shades the meshlet surface as every isosurface path shades its fragments.
#include "common/shading.glsl"
#include "iso/meshlet_draw/params.glsl"

layout(location = 0) in vec3 normal_world;
layout(location = 1) in vec3 position_world;
layout(location = 0) out vec4 colour;

void main() {
    colour = vec4(shade_surface(normal_world, position_world, params.eye_world, params.light), 1.0);
}
