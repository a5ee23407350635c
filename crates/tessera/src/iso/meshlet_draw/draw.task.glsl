#version 460
// Per meshlet of the extraction, a frustum test of its box; the survivors go to one mesh
// workgroup each (paper C's rendering of persistent meshlets).
#extension GL_EXT_mesh_shader : require
#include "iso/meshlet_draw/params.glsl"
#include "iso/meshlet_draw/buffers.glsl"
#include "iso/meshlet_draw/payload.glsl"

layout(local_size_x = MESHLET_DRAW_TASK_SIZE) in;

shared uint visible;

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        visible = 0u;
    }
    barrier();
    uint id = meshlet_group() * MESHLET_DRAW_TASK_SIZE + gl_LocalInvocationIndex;
    if (id < meshlets_to_draw() && meshlet_in_frustum(meshlets[id])) {
        payload.meshlet_ids[atomicAdd(visible, 1u)] = id;
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && visible > 0u) {
        atomicAdd(meshlets_drawn, visible);
    }
    EmitMeshTasksEXT(visible, 1u, 1u);
}
