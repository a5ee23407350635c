#version 460
// One vertex per patch to render (patches of one control point), instances of
// patches_per_instance vertices: the vertex carries its patch's index in the render list.
#include "param/tess_params.glsl"

layout(location = 0) out uint v_patch;

void main() {
    v_patch = uint(gl_InstanceIndex) * params.patches_per_instance + uint(gl_VertexIndex);
    gl_Position = vec4(0.0);
}
