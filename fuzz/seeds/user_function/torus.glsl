// u: 0 2pi
// v: 0 tau
/* a torus */
vec3 f(float u, float v) {
    return vec3((1.0 + 0.3*cos(v))*cos(u), (1.0 + 0.3*cos(v))*sin(u), 0.3*sin(v));
}
