#version 460
// The intersection shader of rt_trace.glsl's hit group SHELL_HIT_GROUP: tests the shell face of
// the box the ray reached in the ray space the ray-generation shader traverses (the same
// origin; the direction reversed again for HIT_GROUP_ENTRY_BEHIND) and reports it when it is
// crossed the way and within the range the group looks for. The attribute carries the
// distance along the traversed ray.
#include "tet/shell/stage.glsl"
#include "tet/shell/buffers.glsl"
#include "tet/shell/params.glsl"
#include "tet/shell/ray_space.glsl"
#include "tet/shell/hit.glsl"

hitAttributeEXT float traversed_t;

void main() {
    bool behind = SHELL_HIT_GROUP == HIT_GROUP_ENTRY_BEHIND;
    vec3 dir = behind ? -gl_WorldRayDirectionEXT : gl_WorldRayDirectionEXT;
    RaySpace ray = ray_space_of_unit(gl_WorldRayOriginEXT, dir);
    float t;
    int side = shell_crossing(ray, uint(gl_PrimitiveID), t);
    traversed_t = t;
    if (SHELL_HIT_GROUP == HIT_GROUP_EXIT) {
        if (side == 1 && t > gl_RayTminEXT) {
            reportIntersectionEXT(t, 0u);
        }
    } else if (!behind) {
        if (side == -1 && t >= gl_RayTminEXT && t < gl_RayTmaxEXT) {
            reportIntersectionEXT(t, 0u);
        }
    } else if (side == -1 && t < 0.0) {
        reportIntersectionEXT(-t, 0u);
    }
}
