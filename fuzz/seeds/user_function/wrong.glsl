vec2 f(float u) { return vec2(u); }
