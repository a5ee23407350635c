// The ray-centric 2-D projection of tessera_data::tet::shell (projection.rs) in f32: the same
// basis, the same per-edge predicate evaluated with the lower vertex id first, the same
// symbolic tie-break and the same corner order for crossing distances, so both tets sharing a
// face reach one verdict and one distance. `precise` keeps the compiler from fusing the cross
// products differently at different call sites.
// Needs buffers.glsl and params.glsl.

struct RaySpace {
    vec3 origin;
    vec3 dir;  // unit
    vec3 u;
    vec3 v;    // u × v = dir
};

// A vertex in ray space: p.xy across the ray, p.z the distance along it; s its scalar in [0, 1].
struct Projected {
    vec3 p;
    uint id;
    float s;
};

// The ray space of a direction already of unit length (a hit shader rebuilding the space of
// the ray it was traced for must not normalize it a second time).
RaySpace ray_space_of_unit(vec3 origin, vec3 dir) {
    vec3 helper = abs(dir.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 u = normalize(cross(dir, helper));
    return RaySpace(origin, dir, u, cross(dir, u));
}

RaySpace ray_space(vec3 origin, vec3 dir) {
    return ray_space_of_unit(origin, normalize(dir));
}

// As tessera_data::tet::scalar_integral::normalize_scalar.
float normalized_scalar(float value) {
    float extent = params.scalar_range.y - params.scalar_range.x;
    return extent > 0.0 ? clamp((value - params.scalar_range.x) / extent, 0.0, 1.0) : 0.0;
}

Projected project(RaySpace ray, uint id) {
    vec4 vertex = vertices[id];
    vec3 d = vertex.xyz - ray.origin;
    return Projected(vec3(dot(d, ray.u), dot(d, ray.v), dot(d, ray.dir)), id, normalized_scalar(vertex.w));
}

float cross2(vec2 a, vec2 b) {
    precise float c = a.x * b.y - a.y * b.x;
    return c;
}

// True when the ray passes on the left of the directed edge a → b in ray space.
bool ray_left_of(Projected a, Projected b) {
    bool flip = a.id > b.id;
    vec2 lo = flip ? b.p.xy : a.p.xy;
    vec2 hi = flip ? a.p.xy : b.p.xy;
    float c = cross2(lo, hi);
    bool left;
    if (c != 0.0) {
        left = c > 0.0;
    } else if (hi.y - lo.y != 0.0) {
        // The ray meets the edge's line: as if it sat at (ε, ε²).
        left = hi.y - lo.y < 0.0;
    } else {
        left = hi.x - lo.x >= 0.0;
    }
    return left != flip;
}

// Where the ray meets the plane of triangle a, b, c: (distance, scalar there), from the ray's
// barycentric coordinates in ray space with the corners in id order. A triangle seen edge-on
// gives its nearest corner.
vec2 crossing(Projected a, Projected b, Projected c) {
    // Sort by id (three compare-swaps).
    Projected t;
    if (a.id > b.id) { t = a; a = b; b = t; }
    if (b.id > c.id) { t = b; b = c; c = t; }
    if (a.id > b.id) { t = a; a = b; b = t; }
    vec3 w = vec3(cross2(b.p.xy, c.p.xy), cross2(c.p.xy, a.p.xy), cross2(a.p.xy, b.p.xy));
    precise float sum = w.x + w.y + w.z;
    precise float depth = (w.x * a.p.z + w.y * b.p.z + w.z * c.p.z) / sum;
    if (sum != 0.0 && !isinf(depth) && !isnan(depth)) {
        return vec2(depth, (w.x * a.s + w.y * b.s + w.z * c.s) / sum);
    }
    Projected nearest = a.p.z <= b.p.z ? (a.p.z <= c.p.z ? a : c) : (b.p.z <= c.p.z ? b : c);
    return vec2(nearest.p.z, nearest.s);
}
