// The view a vertex or fragment belongs to. With MULTIVIEW, one pass renders several views
// (a stereo pair) and each takes its projection and eye from the Views buffer by gl_ViewIndex;
// otherwise the push constants hold the one view. Needs iso/direct/params.glsl.
#if MULTIVIEW
// The layout of iso::direct::stereo::StereoViews.
layout(binding = 5) readonly buffer Views {
    mat4 grid_to_clip[2];
    vec4 eye_world[2];
} views;
mat4 view_grid_to_clip() { return views.grid_to_clip[gl_ViewIndex]; }
vec3 view_eye_world() { return views.eye_world[gl_ViewIndex].xyz; }
#else
mat4 view_grid_to_clip() { return params.grid_to_clip; }
vec3 view_eye_world() { return params.eye_world; }
#endif
