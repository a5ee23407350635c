#version 460
// sh-raytrace's probe pass, for tests and diagnostics: traces the camera rays through given
// raster positions exactly as the image pass does and reports what each hit.
#include "param/raytrace_trace.glsl"

layout(local_size_x = 64) in;
struct RayHit {
    vec4 position;  // xyz: world hit point, w: t along the unit ray from the eye
    vec4 normal;    // xyz: world normal (0 where degenerate), w: unused
    vec4 colour;    // rgb: base colour (by direction), a: 1
    uint glyph;     // RT_NONE for a miss
    uint pad0;
    uint pad1;
    uint pad2;
};
layout(binding = 7, std430) readonly buffer Probes { vec2 probes[]; };
layout(binding = 8, std430) writeonly buffer Hits { RayHit hits[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.count) {
        return;
    }
    vec3 dir = rt_camera_ray(probes[i], vec2(params.size * params.supersample));
    float t;
    uint glyph = rt_trace(params.eye.xyz, dir, t);
    // Written field by field: a RayHit local would be a second SPIR-V type of that name, and
    // the layout test reads the first.
    vec3 position = params.eye.xyz + t * dir;
    vec3 normal = vec3(0.0);
    vec3 colour = vec3(0.0);
    if (glyph != RT_NONE) {
        rt_surface(glyph, position, normal, colour);
    }
    bool hit = glyph != RT_NONE;
    hits[i].position = hit ? vec4(position, t) : vec4(0.0);
    hits[i].normal = vec4(normal, 0.0);
    hits[i].colour = vec4(colour, hit ? 1.0 : 0.0);
    hits[i].glyph = glyph;
    hits[i].pad0 = 0u;
    hits[i].pad1 = 0u;
    hits[i].pad2 = 0u;
}
