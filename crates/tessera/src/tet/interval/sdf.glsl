// The asteroid field of paper A §3.2: a noise-displaced sphere inside each tet, sphere-traced
// along the pixel's interval in that tet. Mirrors tessera_data::tet::asteroids in f32, with its
// constants as defines (SDF_*). Needs params.glsl and length.glsl.

uvec3 pcg3d(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

float value_noise(vec3 p, uint seed) {
    vec3 cell = floor(p);
    vec3 f = p - cell;
    vec3 fade = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    ivec3 base = ivec3(cell);
    float v[8];
    for (int i = 0; i < 8; ++i) {
        ivec3 c = base + ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
        uvec3 h = pcg3d(uvec3(uint(c.x), uint(c.y), uint(c.z) ^ (seed * 0x9E3779B9u)));
        v[i] = float(h.x >> 8) / 16777216.0;
    }
    float x00 = mix(v[0], v[1], fade.x);
    float x10 = mix(v[2], v[3], fade.x);
    float x01 = mix(v[4], v[5], fade.x);
    float x11 = mix(v[6], v[7], fade.x);
    return mix(mix(x00, x10, fade.y), mix(x01, x11, fade.y), fade.z);
}

float fbm(vec3 p, uint seed) {
    float sum = 0.0;
    float amplitude = 1.0;
    for (int o = 0; o < SDF_OCTAVES; ++o) {
        sum += amplitude * (value_noise(p, seed) - 0.5);
        amplitude *= 0.5;
        p *= 2.0;
    }
    return sum;
}

float asteroid_distance(vec3 p, vec4 sphere, uint seed) {
    vec3 q = p - sphere.xyz;
    return length(q) - sphere.w * (1.0 + SDF_AMPLITUDE * fbm(q / sphere.w * SDF_FREQUENCY, seed));
}

// Sphere tracing over [t0, t1] of the unit ray; the hit's distance, or -1.
float asteroid_trace(vec3 eye, vec3 dir, float t0, float t1, vec4 sphere, uint seed) {
    float epsilon = SDF_EPSILON * sphere.w;
    float t = t0;
    for (int i = 0; i < SDF_STEPS; ++i) {
        float d = asteroid_distance(eye + dir * t, sphere, seed);
        if (d < epsilon) {
            return t;
        }
        t += d * SDF_STEP_SCALE;
        if (t > t1) {
            return -1.0;
        }
    }
    return -1.0;
}

vec3 asteroid_shade(vec3 p, vec4 sphere, uint seed) {
    float h = SDF_EPSILON * sphere.w;
    vec3 n = vec3(
        asteroid_distance(p + vec3(h, 0, 0), sphere, seed) - asteroid_distance(p - vec3(h, 0, 0), sphere, seed),
        asteroid_distance(p + vec3(0, h, 0), sphere, seed) - asteroid_distance(p - vec3(0, h, 0), sphere, seed),
        asteroid_distance(p + vec3(0, 0, h), sphere, seed) - asteroid_distance(p - vec3(0, 0, h), sphere, seed));
    float len = length(n);
    n = len > 0.0 ? n / len : vec3(0.0);
    float lit = SDF_AMBIENT + (1.0 - SDF_AMBIENT) * max(dot(n, normalize(SDF_LIGHT)), 0.0);
    float tone = value_noise((p - sphere.xyz) / sphere.w * 4.0, seed ^ 1u);
    return lit * mix(SDF_DARK_ROCK, SDF_LIGHT_ROCK, tone);
}

// The unit world-space direction of the ray through NDC point `ndc`: the line where the clip
// x/w and y/w planes of world_to_clip meet, pointing the way clip w grows (the view depth).
vec3 ray_direction(vec2 ndc) {
    mat4 m = transpose(params.world_to_clip);  // rows of world_to_clip as columns
    vec3 w_row = m[3].xyz;
    vec3 d = cross(m[0].xyz - ndc.x * w_row, m[1].xyz - ndc.y * w_row);
    d = normalize(d);
    return dot(d, w_row) < 0.0 ? -d : d;
}

// How far behind the nearest hit so far (in NDC depth) an interval must begin not to be traced:
// a depth along the ray grows with the distance, and this covers the rounding of the interval's
// entry depth and of a hit's (a few units in the last place near 1).
const float NEARER_SLACK = 1e-6;

// The asteroid hit along this pixel's interval in tet `tet`: xyz colour and w its NDC depth,
// or w < 0 for none, also where the interval begins behind NDC depth `nearest` (the nearest hit
// so far; 1e30 for none), whose hit could not be nearer. The view depths of the interval come
// from the proxies' 1/z.
vec4 asteroid_hit(uint tet, vec4 attrs, vec2 ndc, float nearest) {
    vec3 dir = ray_direction(ndc);
    vec3 forward = transpose(params.world_to_clip)[3].xyz;
    float cos_view = dot(dir, forward);
    float other = second_inverse_depth(attrs);
    float z_front = 1.0 / max(attrs.x, other);
    float z_back = 1.0 / min(attrs.x, other);
    vec3 eye = params.eye.xyz;
    float t_front = z_front / cos_view;
    if (nearest < 1e30) {
        vec4 entry = params.world_to_clip * vec4(eye + dir * t_front, 1.0);
        if (entry.z / entry.w > nearest + NEARER_SLACK) {
            return vec4(0.0, 0.0, 0.0, -1.0);
        }
    }
    vec4 sphere = absorption[tet];
    float t = asteroid_trace(eye, dir, t_front, z_back / cos_view, sphere, tet);
    if (t < 0.0) {
        return vec4(0.0, 0.0, 0.0, -1.0);
    }
    vec3 p = eye + dir * t;
    vec4 clip = params.world_to_clip * vec4(p, 1.0);
    return vec4(asteroid_shade(p, sphere, tet), clip.z / clip.w);
}
