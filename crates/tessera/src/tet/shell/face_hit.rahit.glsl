#version 460
// The any-hit shader of rt_trace.glsl's hit group SHELL_HIT_GROUP: keeps the reported face in
// the payload when it beats the best so far; accepts it (shortening the ray) where the group
// wants the nearest hit, and ignores every face where it wants the farthest.
#include "tet/shell/stage.glsl"
#include "tet/shell/buffers.glsl"
#include "tet/shell/params.glsl"
#include "tet/shell/ray_space.glsl"
#include "tet/shell/hit.glsl"

hitAttributeEXT float traversed_t;
layout(location = 0) rayPayloadInEXT ShellHit shell_best;

void main() {
    uint face = uint(gl_PrimitiveID);
    bool better = SHELL_HIT_GROUP == HIT_GROUP_EXIT ? better_exit(traversed_t, face, shell_best)
                                                     : better_entry(traversed_t, face, shell_best);
    if (better) {
        shell_best = ShellHit(traversed_t, face);
    }
    if (!better || SHELL_HIT_GROUP == HIT_GROUP_ENTRY_AHEAD) {
        ignoreIntersectionEXT;
    }
}
