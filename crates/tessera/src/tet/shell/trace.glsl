// shell_trace() for the pass's way of tracing (stage.glsl).
// Needs buffers.glsl, ray_space.glsl and hit.glsl.
#if SHELL_RAY_TRACING
#include "tet/shell/rt_trace.glsl"
#else
#include "tet/shell/bvh.glsl"
#endif
