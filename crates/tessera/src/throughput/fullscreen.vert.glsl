#version 460
// One triangle that covers the whole viewport: vertices (-1,-1), (3,-1), (-1,3) in NDC. Unlike
// two triangles it has no diagonal seam, so no pixel is shaded twice.

void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
