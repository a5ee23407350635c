// The traces of Alg. 1 against the shell BVH, in the ray space of the ray being traversed:
// the nearest face the ray leaves through beyond a distance (the trace with front faces
// culled), and the farthest face it enters through before one (the backward trace from the
// exit, front faces of the reversed ray culled), faces judged as hit.glsl says. The whole line
// is searched, so an entry face behind the origin (an eye inside the mesh) is found too.
// Needs buffers.glsl, ray_space.glsl and hit.glsl.

// Parameter range [near, far] of the ray's line inside a node's box.
vec2 box_span(RaySpace ray, vec3 inv_dir, uint node) {
    vec3 a = (bvh_nodes[node].lo - ray.origin) * inv_dir;
    vec3 b = (bvh_nodes[node].hi - ray.origin) * inv_dir;
    vec3 near = min(a, b);
    vec3 far = max(a, b);
    return vec2(max(max(near.x, near.y), near.z), min(min(far.x, far.y), far.z));
}

// Whether a box the ray's line spans over [span.x, span.y] may hold a better face than `best`
// (the window as shell_trace's arguments and its best face so far set it).
bool span_reaches(vec2 span, bool leaving, float lo, float hi, ShellHit best) {
    float window_lo = leaving ? lo : best.t;
    float window_hi = leaving ? best.t : hi;
    return span.x <= span.y && span.y >= window_lo && span.x <= window_hi;
}

// leaving: the nearest leaving face with t > lo. Else: the farthest entering face with
// lo <= t < hi. An inner node's two children are tested together, so that a child the ray
// misses is never visited and each child's box is read once for both the test and the order:
// the child the ray meets first for the nearest exit (the one it leaves last for the farthest
// entry) is walked first, and the best face found there prunes more of the other. A child put
// on the stack is tested again when it comes off, against the best face by then. The order
// does not change the face found (ties go by face index, not by visit).
ShellHit shell_trace(RaySpace ray, bool leaving, float lo, float hi) {
    // A zero component would make 0 * inf in the slab test; a tiny one only widens the span.
    vec3 inv_dir = 1.0 / mix(vec3(1e-30), ray.dir, greaterThan(abs(ray.dir), vec3(1e-30)));
    ShellHit best = ShellHit(leaving ? hi : lo, NO_FACE);
    uint stack[BVH_MAX_DEPTH + 1];
    uint top = 0u;
    uint node = 0u;
    bool reached = span_reaches(box_span(ray, inv_dir, 0u), leaving, lo, hi, best);
    while (true) {
        if (reached) {
            uint first = bvh_nodes[node].first;
            uint count = bvh_nodes[node].count;
            if (count == 0u) {
                vec2 span_a = box_span(ray, inv_dir, first);
                vec2 span_b = box_span(ray, inv_dir, first + 1u);
                bool reaches_a = span_reaches(span_a, leaving, lo, hi, best);
                bool reaches_b = span_reaches(span_b, leaving, lo, hi, best);
                bool b_first = reaches_b
                    && (!reaches_a || (leaving ? span_b.x < span_a.x : span_b.y > span_a.y));
                if (reaches_a && reaches_b && top <= uint(BVH_MAX_DEPTH)) {
                    stack[top++] = b_first ? first : first + 1u;
                }
                node = b_first ? first + 1u : first;
                reached = reaches_a || reaches_b;
                continue;
            }
            for (uint f = first; f < first + count; ++f) {
                float t;
                int side = shell_crossing(ray, f, t);
                bool better;
                if (leaving) {
                    better = side == 1 && t > lo && better_exit(t, f, best);
                } else {
                    better = side == -1 && t >= lo && t < hi && better_entry(t, f, best);
                }
                if (better) {
                    best = ShellHit(t, f);
                }
            }
        }
        if (top == 0u) {
            break;
        }
        node = stack[--top];
        reached = span_reaches(box_span(ray, inv_dir, node), leaving, lo, hi, best);
    }
    return best;
}
