// The buffers every interval-shading pass binds first (host side: `Interval`'s common bindings).
layout(binding = 0) readonly buffer Vertices { vec4 vertices_world[]; };  // xyz, w = scalar in [0, 1]
layout(binding = 1) readonly buffer Tets { uvec4 tets[]; };
layout(binding = 2) readonly buffer Absorption { vec4 absorption[]; };  // per tet, rgb
// The integrand table: TABLE_KNOTS values, then their running integral (integrand.glsl).
layout(binding = 3) readonly buffer Table { vec4 table[]; };
layout(binding = 4) buffer Stats { uint stats[]; };  // [0] clipped tets, [1] tiled tets, [2] overflow
