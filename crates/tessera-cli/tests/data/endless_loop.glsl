// u: 0 pi
// v: 0 2pi
vec3 f(float u, float v) {
    float s = 0.0;
    for (int i = 0; i >= 0; i += 0) { s += sin(s + u); if (s > 1e30) break; }
    return vec3(sin(u) * cos(v), sin(u) * sin(v), cos(u) + s * 1e-30);
}
