// The view a vertex or fragment belongs to. With MULTIVIEW, one pass renders several views
// (a stereo pair) and each takes its projection and eye from the Views buffer by gl_ViewIndex;
// otherwise the push constants hold the one view. Needs iso/direct/params.glsl.
#if MULTIVIEW
layout(binding = 5) readonly buffer Views {
    mat4 views_grid_to_clip[2];
    vec4 views_eye_world[2];
};
mat4 view_grid_to_clip() { return views_grid_to_clip[gl_ViewIndex]; }
vec3 view_eye_world() { return views_eye_world[gl_ViewIndex].xyz; }
#else
mat4 view_grid_to_clip() { return params.grid_to_clip; }
vec3 view_eye_world() { return params.eye_world; }
#endif
