#version 460
// Marks covered pixels with all bits set, the value the compute splat stores.

layout(location = 0) out vec4 color;

void main() {
    color = vec4(1.0);
}
