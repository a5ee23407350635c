// Included first by every shell pass: with SHELL_RAY_TRACING the pass is compiled as a
// ray-generation shader whose shell traces go through the acceleration structure
// (rt_trace.glsl), else as a compute shader walking the BVH itself (bvh.glsl). The hit shaders
// (face_hit.*.glsl) include it too, for the extension.
#if SHELL_RAY_TRACING
#extension GL_EXT_ray_tracing : require
#define INVOCATION_ID gl_LaunchIDEXT
#else
#define INVOCATION_ID gl_GlobalInvocationID
#endif
