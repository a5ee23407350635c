// What a shell trace finds and how a face is judged, for both ways of tracing (the BVH walk of
// bvh.glsl and the acceleration structure of rt_trace.glsl): each face is tested with the
// marching's own edge predicates, so the face found agrees with the steps after it, and ties
// go to the face first in the buffer for exits and last for entries, as the CPU reference's
// sorted hits.
// Needs buffers.glsl and ray_space.glsl.

const uint NO_FACE = 0xffffffffu;

struct ShellHit {
    float t;
    uint face;  // index into shell_faces, NO_FACE when none
};

// How the ray crosses shell face f: 1 leaving, -1 entering, 0 missing; t where.
int shell_crossing(RaySpace ray, uint f, out float t) {
    uvec4 face = shell_faces[f];
    Projected a = project(ray, face.x);
    Projected b = project(ray, face.y);
    Projected c = project(ray, face.z);
    bool ab = ray_left_of(a, b);
    bool bc = ray_left_of(b, c);
    bool ca = ray_left_of(c, a);
    t = 0.0;
    if (ab != bc || bc != ca) {
        return 0;
    }
    t = crossing(a, b, c).x;
    return ab ? 1 : -1;
}

// Whether leaving face f at t beats `best` for the nearest exit.
bool better_exit(float t, uint f, ShellHit best) {
    return t < best.t || (t == best.t && (best.face == NO_FACE || f < best.face));
}

// Whether entering face f at t beats `best` for the farthest entry.
bool better_entry(float t, uint f, ShellHit best) {
    return t > best.t || (t == best.t && (best.face == NO_FACE || f > best.face));
}
