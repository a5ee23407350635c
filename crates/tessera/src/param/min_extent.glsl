// A lower bound on the screen extents of an SH glyph's patch, from the glyph's bounding
// sphere: its angular ranges times the sphere's projected radius, i.e. the length those ranges
// span on screen at the largest radius the glyph may reach. The LOD stage measures a patch
// along 8-sample lines, which pass between the thin lobes of a small glyph: the patch is then
// measured small and drawn with too few samples. Drawing with at least this extent keeps about
// one sample per pixel along the bounding sphere, so no lobe falls between samples. Only
// normalized glyphs have a known bound (radius_map.w, the upper clamp); other objects get 0.

#ifndef PARAM_MIN_EXTENT_GLSL
#define PARAM_MIN_EXTENT_GLSL

#include "param/scene.glsl"
#include "param/view.glsl"
#include "param/patch.glsl"

// PARAM_MIN_EXTENT_FACTOR (samples per pixel along the bounding sphere's arcs) comes from Rust
// (param/points.rs, MIN_EXTENT_FACTOR).

// Largest pixel distance from the projected centre to the projected ends of the world-axis
// radii: the sphere's projected radius, to within the factor a perspective view distorts it.
float param_projected_radius(vec3 centre, float radius, mat4 world_to_clip, vec2 viewport) {
    vec2 middle;
    float depth;
    if (!param_project(world_to_clip, viewport, centre, middle, depth)) {
        return 0.0;
    }
    float largest = 0.0;
    for (uint axis = 0u; axis < 3u; ++axis) {
        vec3 offset = vec3(0.0);
        offset[axis] = radius;
        for (float side = -1.0; side <= 1.0; side += 2.0) {
            vec2 end;
            if (param_project(world_to_clip, viewport, centre + side * offset, end, depth)) {
                largest = max(largest, distance(end, middle));
            }
        }
    }
    return largest;
}

vec2 param_min_extent(Patch p, mat4 world_to_clip, vec2 viewport) {
    ParamObject o = param_objects[p.object];
    // A patch the LOD stage split came from a glyph measured large, whose lines were dense
    // enough to find its lobes; only patches it kept at once were measured too coarsely.
    bool kept_at_once = (p.info & 0xffffu) == 0u;
    if (!kept_at_once || o.kind != PARAM_KIND_SH_GLYPH || !(o.radius_map.w <= 1.0)) {
        return vec2(0.0);
    }
    // Object to world scales by at most the longest column of the model's 3x3 part.
    vec3 c0 = vec3(o.model[0].x, o.model[1].x, o.model[2].x);
    vec3 c1 = vec3(o.model[0].y, o.model[1].y, o.model[2].y);
    vec3 c2 = vec3(o.model[0].z, o.model[1].z, o.model[2].z);
    float scale = max(length(c0), max(length(c1), length(c2)));
    vec3 centre = vec3(o.model[0].w, o.model[1].w, o.model[2].w);
    float pixels = param_projected_radius(centre, o.radius_map.w * scale, world_to_clip, viewport);
    return vec2(p.u.y - p.u.x, p.v.y - p.v.x) * pixels * PARAM_MIN_EXTENT_FACTOR;
}

#endif
