// u: -1 1
// v: -0.5*pi pi
float g(float x) { return x * x; }
vec3 f(float a, float b) { return vec3(a, b, g(a)); }
vec3 h(float u) { return f(u, u); }
