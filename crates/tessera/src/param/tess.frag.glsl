#version 460
// Shades the surface point the fragment sees at its interpolated (u, v), as the point variant's
// resolve does. Centroid interpolation keeps (u, v) on the covered part of a multisampled pixel.
// TESS_DEBUG_LEVELS (tests): the patch's inner levels as colour instead, (r, g) = level / 255.
#include "param/shade.glsl"
#include "param/tess_params.glsl"

layout(location = 0) centroid in vec2 te_uv;
layout(location = 1) flat in uint te_object;
layout(location = 0) out vec4 colour;
#ifdef TESS_DEBUG_LEVELS
layout(location = 2) flat in vec2 te_inner;
#endif

void main() {
#ifdef TESS_DEBUG_LEVELS
    colour = vec4(te_inner / 255.0, 0.0, 1.0);
#else
    colour = vec4(param_shade(te_object, te_uv.x, te_uv.y, params.eye.xyz, params.light.xyz), 1.0);
#endif
}
