// The traces of Alg. 1 through the ray-tracing pipeline. The acceleration structure holds a box
// around each shell face (primitive i = shell_faces[i]); the hit groups test each face whose
// box the ray reaches with hit.glsl's predicates in the ray's own ray space and keep the best
// face in the payload by hit.glsl's rules, so both ways of tracing find the same faces:
// - HIT_GROUP_EXIT: the nearest leaving face beyond lo; a better face is accepted, which
//   shortens the ray, so farther boxes are skipped.
// - HIT_GROUP_ENTRY_AHEAD: the farthest entering face in [max(lo, 0), hi); every face in the
//   range is looked at (nearest-first order does not help a search for the farthest).
// - HIT_GROUP_ENTRY_BEHIND: with none there and lo < 0 (an origin inside the mesh), the ray is
//   traced backwards from the origin, where the farthest entry is the nearest hit.
// Rays start at t = 0 or beyond: a trace cannot begin behind its origin.
// Needs buffers.glsl, ray_space.glsl and hit.glsl.

layout(binding = SHELL_SCENE_BINDING) uniform accelerationStructureEXT shell_scene;
layout(location = 0) rayPayloadEXT ShellHit shell_best;

// The largest finite float: a trace's range must be finite.
const float FARTHEST = 3.4028234e38;

ShellHit shell_trace(RaySpace ray, bool leaving, float lo, float hi) {
    float t_min = max(lo, 0.0);
    float t_max = min(hi, FARTHEST);
    if (leaving) {
        shell_best = ShellHit(hi, NO_FACE);
        if (t_min < t_max) {
            traceRayEXT(shell_scene, gl_RayFlagsNoneEXT, 0xff, HIT_GROUP_EXIT, 0, 0, ray.origin, t_min, ray.dir,
                        t_max, 0);
        }
        return shell_best;
    }
    shell_best = ShellHit(lo, NO_FACE);
    if (t_min < t_max) {
        traceRayEXT(shell_scene, gl_RayFlagsNoneEXT, 0xff, HIT_GROUP_ENTRY_AHEAD, 0, 0, ray.origin, t_min, ray.dir,
                    t_max, 0);
    }
    if (shell_best.face == NO_FACE && lo < 0.0) {
        traceRayEXT(shell_scene, gl_RayFlagsNoneEXT, 0xff, HIT_GROUP_ENTRY_BEHIND, 0, 0, ray.origin, 0.0, -ray.dir,
                    min(-lo, FARTHEST), 0);
    }
    return shell_best;
}
