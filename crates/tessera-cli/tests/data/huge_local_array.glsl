// u: 0 pi
// v: 0 2pi
vec3 f(float u, float v) {
    float table[1000000];
    for (int i = 0; i < 1000000; ++i) {
        table[i] = float(i) * u;
    }
    return vec3(sin(u) * cos(v), sin(u) * sin(v), cos(u) + table[int(v)] * 1e-9);
}
