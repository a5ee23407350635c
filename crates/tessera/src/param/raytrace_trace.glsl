// Tracing a ray through a scene of SH glyphs (param/raytrace.rs documents the buffers): a
// uniform grid of glyph cells walked by a 3D DDA (Amanatides & Woo), each glyph's world
// bounding sphere tested before the polynomial of raytrace_glyph.glsl, a small mailbox so that a
// glyph listed in several cells is solved once per ray; then the hit is shaded as param-points'
// resolve shades (two-sided Lambert + ambient, colour by direction), with the normal from finite
// differences of the glyph's implicit form |p| - min(|r(p/|p|)|, B) in object space.

#ifndef PARAM_RAYTRACE_TRACE_GLSL
#define PARAM_RAYTRACE_TRACE_GLSL

#include "param/raytrace_glyph.glsl"

struct RtGlyph {
    vec4 to_object[3];  // rows of the world-to-object 3x4 matrix
    vec4 sphere;        // world-space bounding sphere: centre, radius
    vec4 shape;         // x: object-space bounding radius B (the clamp of normalised glyphs)
};

layout(binding = 3, std430) readonly buffer RtGlyphs { RtGlyph rt_glyphs[]; };
layout(binding = 4, std430) readonly buffer RtGrid {
    vec4 grid_lo;    // xyz: lowest corner
    vec4 grid_cell;  // xyz: cell size
    uvec4 grid_dims; // xyz: cells per axis
    uint grid_cell_start[];  // cell i lists rt_items[start[i] .. start[i + 1]]
};
layout(binding = 5, std430) readonly buffer RtItems { uint rt_items[]; };

// The camera and frame, shared by the image and probe passes (RaytraceParams in raytrace.rs).
layout(push_constant) uniform RaytraceParams {
    vec4 eye;         // world space
    vec4 ray_centre;  // ray direction (unnormalised) through NDC (0, 0)
    vec4 ray_x;       // its change per unit of NDC x
    vec4 ray_y;       // its change per unit of NDC y
    vec4 light;       // unit direction towards the light
    vec4 background;  // rgb
    uvec2 size;       // image width, height
    uint supersample; // rays per image pixel along each axis
    uint count;       // probe pass: probes to trace
} params;

const float RT_FAR = 3.0e38;
const uint RT_NONE = 0xffffffffu;
const uint RT_MAILBOX = 8u;

// The records are read field by field rather than copied whole, which keeps RtGlyph's SPIR-V
// type the decorated buffer one (the layout test reads its offsets).
vec3 rt_object_point(uint index, vec3 p) {
    vec4 h = vec4(p, 1.0);
    return vec3(dot(rt_glyphs[index].to_object[0], h), dot(rt_glyphs[index].to_object[1], h),
                dot(rt_glyphs[index].to_object[2], h));
}

vec3 rt_object_vector(uint index, vec3 v) {
    return vec3(dot(rt_glyphs[index].to_object[0].xyz, v), dot(rt_glyphs[index].to_object[1].xyz, v),
                dot(rt_glyphs[index].to_object[2].xyz, v));
}

// The hit of the world ray origin + t dir (dir of unit length) with glyph `index` before t_max.
bool rt_hit_glyph(uint index, vec3 origin, vec3 dir, float t_max, out float t) {
    vec4 sphere = rt_glyphs[index].sphere;
    t = t_max;
    // Bounding sphere, from the ray's closest approach to avoid |oc|^2 - r^2 cancelling.
    vec3 oc = origin - sphere.xyz;
    float along = dot(oc, dir);
    vec3 off = oc - along * dir;
    float disc = sphere.w * sphere.w - dot(off, off);
    if (disc < 0.0) {
        return false;
    }
    float s = sqrt(disc);
    if (-along - s > t_max || -along + s < 0.0) {
        return false;
    }
    vec3 d = rt_object_vector(index, dir);
    float len = length(d);
    float t_object;
    vec3 o = rt_object_point(index, origin);
    float limit = t_max >= RT_FAR ? RT_FAR : t_max * len;  // no infinities in shaders
    if (!rt_intersect_glyph(index, rt_glyphs[index].shape.x, o, d / len, 0.0, limit, t_object)) {
        return false;
    }
    t = t_object / len;
    return t < t_max;
}

// Nearest glyph along the world ray origin + t dir (dir of unit length), RT_NONE if none.
uint rt_trace(vec3 origin, vec3 dir, out float best_t) {
    best_t = RT_FAR;
    uint best = RT_NONE;
    // Axis-parallel rays: a tiny component of the same sign keeps every t finite.
    vec3 safe = mix(dir, sign(dir) * 1e-20 + vec3(equal(dir, vec3(0.0))) * 1e-20, lessThan(abs(dir), vec3(1e-20)));
    vec3 inv = 1.0 / safe;
    ivec3 dims = ivec3(grid_dims.xyz);
    vec3 hi = grid_lo.xyz + grid_cell.xyz * vec3(dims);
    vec3 t0 = (grid_lo.xyz - origin) * inv;
    vec3 t1 = (hi - origin) * inv;
    vec3 near = min(t0, t1);
    vec3 far = max(t0, t1);
    float enter = max(max(max(near.x, near.y), near.z), 0.0);
    float exit = min(min(far.x, far.y), far.z);
    if (enter > exit) {
        return RT_NONE;
    }
    ivec3 cell = clamp(ivec3(floor((origin + enter * dir - grid_lo.xyz) / grid_cell.xyz)), ivec3(0), dims - 1);
    ivec3 step = ivec3(sign(safe));
    vec3 next = (grid_lo.xyz + vec3(cell + max(step, ivec3(0))) * grid_cell.xyz - origin) * inv;
    vec3 delta = grid_cell.xyz * abs(inv);
    uint mailbox[RT_MAILBOX];
    for (uint i = 0u; i < RT_MAILBOX; ++i) {
        mailbox[i] = RT_NONE;
    }
    uint slot = 0u;
    for (int walked = 0; walked < dims.x + dims.y + dims.z; ++walked) {
        uint index = uint(cell.x + dims.x * (cell.y + dims.y * cell.z));
        for (uint k = grid_cell_start[index]; k < grid_cell_start[index + 1u]; ++k) {
            uint glyph = rt_items[k];
            bool seen = false;
            for (uint i = 0u; i < RT_MAILBOX; ++i) {
                seen = seen || mailbox[i] == glyph;
            }
            if (seen) {
                continue;
            }
            mailbox[slot] = glyph;
            slot = (slot + 1u) % RT_MAILBOX;
            float t;
            if (rt_hit_glyph(glyph, origin, dir, best_t, t)) {
                best_t = t;
                best = glyph;
            }
        }
        int axis = next.x < next.y ? (next.x < next.z ? 0 : 2) : (next.y < next.z ? 1 : 2);
        if (best_t <= min(next[axis], exit) || next[axis] >= exit) {
            break;
        }
        cell[axis] += step[axis];
        if (cell[axis] < 0 || cell[axis] >= dims[axis]) {
            break;
        }
        next[axis] += delta[axis];
    }
    return best;
}

// Unit direction of the ray through raster position `raster` (pixel centres at + 0.5) of a
// raster of `raster_size`: NDC as tessera_data::param::reference projects.
vec3 rt_camera_ray(vec2 raster, vec2 raster_size) {
    vec2 ndc = raster / raster_size * 2.0 - 1.0;
    return normalize(params.ray_centre.xyz + ndc.x * params.ray_x.xyz + ndc.y * params.ray_y.xyz);
}

// |p| - min(|r(p / |p|)|, B): negative inside the glyph of `object`.
float rt_implicit(ParamObject o, float bound, vec3 p) {
    return length(p) - min(abs(rt_radius(o, p)), bound);
}

// World normal (not normalised to the eye) and base colour at the world point `position` of
// glyph `index`.
void rt_surface(uint index, vec3 position, out vec3 normal, out vec3 colour) {
    ParamObject o = param_objects[index];
    float bound = rt_glyphs[index].shape.x;
    vec3 p = rt_object_point(index, position);
    float len = length(p);
    colour = len > 0.0 ? abs(p / len) : vec3(0.5);
    // Steps of 1/1000 of the radius: the truncation error (~ (k e / r)^2) and the f32 rounding
    // (~ 1e-7 r / e) both stay near 1e-4 up to order 16.
    float e = 1e-3 * len + 1e-6 * bound;
    // Central differences through one call site (each call inlines the whole SH series; the
    // six written out made the pass several times slower to compile): grad[axis] =
    // (0 + f(p + e)) + -f(p - e), which rounds as f(p + e) - f(p - e).
    vec3 grad = vec3(0.0);
    for (int i = 0; i < 6; ++i) {
        int axis = i >> 1;
        bool ahead = (i & 1) == 0;
        vec3 offset = vec3(0.0);
        offset[axis] = ahead ? e : -e;
        float value = rt_implicit(o, bound, p + offset);
        grad[axis] += ahead ? value : -value;
    }
    // Normals go by the inverse transpose of object-to-world, i.e. the transpose of to_object.
    normal = grad.x * rt_glyphs[index].to_object[0].xyz + grad.y * rt_glyphs[index].to_object[1].xyz
           + grad.z * rt_glyphs[index].to_object[2].xyz;
    float n = length(normal);
    normal = n > 0.0 && !isnan(n) && !isinf(n) ? normal / n : vec3(0.0);
}

// tessera_data::param::reference::shade, as param-points' resolve.
vec3 rt_shade(vec3 normal, vec3 colour, vec3 position, vec3 eye, vec3 light) {
    vec3 view = normalize(eye - position);
    vec3 n = normal == vec3(0.0) ? view : normal;
    if (dot(n, view) < 0.0) {
        n = -n;
    }
    return colour * (SHADE_AMBIENT + SHADE_DIFFUSE * max(dot(n, light), 0.0));
}

#endif
