// Projection of world points to raster pixels, the same arithmetic as ParamView::project in
// param/view.rs (each operation rounded on its own, hence `precise`): clip = world_to_clip * p
// summed column by column, pixel = (clip.xy / clip.w * 0.5 + 0.5) * viewport, depth = z / w.

#ifndef PARAM_VIEW_GLSL
#define PARAM_VIEW_GLSL

// False when the point is not in front of the eye (w <= 0 or not a number).
bool param_project(mat4 world_to_clip, vec2 viewport, vec3 p, out vec2 pixel, out float depth) {
    precise vec4 clip = ((world_to_clip[0] * p.x + world_to_clip[1] * p.y) + world_to_clip[2] * p.z) + world_to_clip[3];
    precise vec2 ndc = clip.xy / clip.w;
    precise vec2 px = (ndc * 0.5 + 0.5) * viewport;
    precise float z = clip.z / clip.w;
    pixel = px;
    depth = z;
    return clip.w > 0.0;
}

#endif
