// Unit vectors in 32 bits: the octahedral map (the sphere folded onto the square |u| + |v| <= 1
// and its lower half unfolded into the corners), each coordinate a 16-bit snorm. Directions
// come back within 1e-4 rad (6.4e-5 the worst of 40,000 in tessera_data's test), which
// decodes the same bits on the CPU (tessera_data::unit_vector).

// No vector has it: packSnorm2x16 writes -1 as 0x8001, never 0x8000. A zero or non-finite
// vector packs to it and unpacks to zero.
const uint PACKED_ZERO_VECTOR = 0x80008000u;

vec2 unit_vector_sign(vec2 v) {
    return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}

uint pack_unit_vector(vec3 v) {
    float l1 = abs(v.x) + abs(v.y) + abs(v.z);
    if (!(l1 > 0.0) || isinf(l1)) {
        return PACKED_ZERO_VECTOR;
    }
    vec2 p = v.xy / l1;
    if (v.z < 0.0) {
        p = (1.0 - abs(p.yx)) * unit_vector_sign(p);
    }
    return packSnorm2x16(p);
}

vec3 unpack_unit_vector(uint packed) {
    if (packed == PACKED_ZERO_VECTOR) {
        return vec3(0.0);
    }
    vec2 p = unpackSnorm2x16(packed);
    vec3 v = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (v.z < 0.0) {
        v.xy = (1.0 - abs(v.yx)) * unit_vector_sign(v.xy);
    }
    return normalize(v);
}
