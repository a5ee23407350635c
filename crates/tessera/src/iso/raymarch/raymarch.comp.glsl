#version 460
// Isosurface ray marching with empty-space skipping through the min-max octree (paper D's
// reference method). Samples lie on a fixed lattice of STEP grid units from the ray's entry, so
// skipping a node whose range excludes the isovalue visits exactly the samples a plain march
// would compare: every skipped sample lies on the same side of the isovalue.
#include "common/volume.glsl"
#include "common/shading.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) readonly buffer Nodes { vec2 minmax_nodes[]; };
layout(binding = 2) readonly buffer Levels { uvec4 levels[]; };  // xyz nodes per axis, w first node
layout(binding = 3) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform RaymarchParams {
    vec3 eye;            // grid space
    float isovalue;
    vec3 forward;        // grid space
    float tan_half_fov_x;
    vec3 right;          // grid space
    float tan_half_fov_y;
    vec4 up;             // grid space (xyz)
    vec4 light;          // world space, towards the light
    vec4 grid_to_world;  // xyz world units per grid unit
    uvec3 dims;          // samples per axis
    uint octree_levels;
    uvec4 image;         // x width, y height
} params;

const uvec3 BLOCK = uvec3(BLOCK_X, BLOCK_Y, BLOCK_Z);

bool node_empty(uint level, uvec3 node, float iso) {
    uvec4 l = levels[level];
    vec2 range = minmax_nodes[l.w + node.x + l.x * (node.y + l.y * node.z)];
    return iso < range.x || iso > range.y;
}

// Distance to the exit of the largest empty octree node holding grid point p, or -1.
float empty_exit(vec3 p, vec3 origin, vec3 inv_dir, float iso) {
    uvec3 dims = params.dims.xyz;
    uvec3 cell = uvec3(clamp(ivec3(floor(p)), ivec3(0), ivec3(dims) - 2));
    int found = -1;
    for (uint level = 0; level < params.octree_levels; ++level) {
        if (!node_empty(level, cell / (BLOCK << level), iso)) {
            break;
        }
        found = int(level);
    }
    if (found < 0) {
        return -1.0;
    }
    uvec3 size = BLOCK << uint(found);
    uvec3 lo = (cell / size) * size;
    uvec3 hi = min(lo + size, dims - 1u);
    return ray_box(origin, inv_dir, vec3(lo), vec3(hi)).y;
}

float refine(vec3 origin, vec3 dir, float iso, float ta, float va, float tb, float vb) {
    for (int i = 0; i < REFINEMENTS; ++i) {
        float tm = 0.5 * (ta + tb);
        precise vec3 pm = origin + dir * tm;
        float vm = sample_volume(volume_tex, pm, params.dims.xyz);
        if ((vm < iso) == (va < iso)) {
            ta = tm;
            va = vm;
        } else {
            tb = tm;
            vb = vm;
        }
    }
    float denom = vb - va;
    float w = denom != 0.0 ? clamp((iso - va) / denom, 0.0, 1.0) : 0.5;
    return ta + (tb - ta) * w;
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, params.image.xy))) {
        return;
    }
    vec2 size = vec2(params.image.xy);
    float sx = (2.0 * (float(pixel.x) + 0.5) / size.x - 1.0) * params.tan_half_fov_x;
    float sy = (1.0 - 2.0 * (float(pixel.y) + 0.5) / size.y) * params.tan_half_fov_y;
    vec3 dir = normalize(params.forward + sx * params.right + sy * params.up.xyz);
    vec3 origin = params.eye;
    float iso = params.isovalue;
    uvec3 dims = params.dims.xyz;
    vec3 inv_dir = 1.0 / dir;

    vec4 colour = BACKGROUND;
    vec2 span = ray_box(origin, inv_dir, vec3(0.0), vec3(dims - 1u));
    span.x = max(span.x, 0.0);
    if (span.x <= span.y) {
        uint steps = uint(floor((span.y - span.x) / STEP));
        uint k = 0;
        precise vec3 p = origin + dir * span.x;
        float v_prev = sample_volume(volume_tex, p, dims);
        float t_hit = -1.0;
        while (k < steps) {
            float exit_t = empty_exit(p, origin, inv_dir, iso);
            if (exit_t >= 0.0) {
                // Stay a hair inside the node so the resumed sample is still known empty.
                uint k_skip = uint(max(floor((exit_t - span.x) / STEP - 1e-3), 0.0));
                if (k_skip > k) {
                    k = min(k_skip, steps);
                    float tk = span.x + float(k) * STEP;
                    p = origin + dir * tk;
                    v_prev = sample_volume(volume_tex, p, dims);
                    continue;
                }
            }
            float t_prev = span.x + float(k) * STEP;
            float t = span.x + float(k + 1u) * STEP;
            p = origin + dir * t;
            float v = sample_volume(volume_tex, p, dims);
            if ((v < iso) != (v_prev < iso)) {
                t_hit = refine(origin, dir, iso, t_prev, v_prev, t, v);
                break;
            }
            v_prev = v;
            k += 1u;
        }
        if (t_hit >= 0.0) {
            precise vec3 hit = origin + dir * t_hit;
            vec3 g = volume_gradient(volume_tex, hit, dims) / params.grid_to_world.xyz;
            vec3 n = dot(g, g) > 0.0 ? normalize(g) : -dir;
            vec3 view = -normalize(dir * params.grid_to_world.xyz);
            colour = vec4(gooch(n, params.light.xyz, view), 1.0);
        }
    }
    pixels[pixel.y * params.image.x + pixel.x] = packUnorm4x8(colour);
}
