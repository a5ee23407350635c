// What a drawn pixel holds below its depth (param/points.rs documents it): the object index in
// the high bits, then u and v quantized over the object's domain to PAYLOAD_UV_BITS each.

#ifndef PARAM_PAYLOAD_GLSL
#define PARAM_PAYLOAD_GLSL

#include "param/scene.glsl"

uint param_payload(uint object, float u, float v, uint uv_bits) {
    vec4 d = param_objects[object].domain;
    float top = float((1u << uv_bits) - 1u);
    uint qu = uint(round(clamp((u - d.x) / (d.y - d.x), 0.0, 1.0) * top));
    uint qv = uint(round(clamp((v - d.z) / (d.w - d.z), 0.0, 1.0) * top));
    uint high = uv_bits >= 16u ? 0u : object << (2u * uv_bits);
    return high | (qu << uv_bits) | qv;
}

// (object, u, v) back from a payload.
void param_unpack(uint payload, uint uv_bits, out uint object, out float u, out float v) {
    uint mask = (1u << uv_bits) - 1u;
    object = uv_bits >= 16u ? 0u : payload >> (2u * uv_bits);
    vec4 d = param_objects[object].domain;
    float top = float(mask);
    u = d.x + (d.y - d.x) * (float((payload >> uv_bits) & mask) / top);
    v = d.z + (d.w - d.z) * (float(payload & mask) / top);
}

#endif
