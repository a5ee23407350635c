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

// leaving: the nearest leaving face with t > lo. Else: the farthest entering face with
// lo <= t < hi.
ShellHit shell_trace(RaySpace ray, bool leaving, float lo, float hi) {
    // A zero component would make 0 * inf in the slab test; a tiny one only widens the span.
    vec3 inv_dir = 1.0 / mix(vec3(1e-30), ray.dir, greaterThan(abs(ray.dir), vec3(1e-30)));
    ShellHit best = ShellHit(leaving ? hi : lo, NO_FACE);
    uint stack[BVH_MAX_DEPTH + 1];
    uint top = 0u;
    uint node = 0u;
    while (true) {
        vec2 span = box_span(ray, inv_dir, node);
        uint first = bvh_nodes[node].first;
        uint count = bvh_nodes[node].count;
        float window_lo = leaving ? lo : best.t;
        float window_hi = leaving ? best.t : hi;
        bool enter = span.x <= span.y && span.y >= window_lo && span.x <= window_hi;
        if (enter && count == 0u && top <= uint(BVH_MAX_DEPTH)) {
            // The nearer child first for the nearest exit, the farther first for the farthest
            // entry: the best face found there then prunes more of the other. The order does
            // not change the face found (ties go by face index, not by visit).
            vec3 a = bvh_nodes[first].lo + bvh_nodes[first].hi;
            vec3 b = bvh_nodes[first + 1u].lo + bvh_nodes[first + 1u].hi;
            float first_beyond_second = dot(a - b, ray.dir);
            bool second_first = leaving ? first_beyond_second > 0.0 : first_beyond_second < 0.0;
            stack[top++] = second_first ? first : first + 1u;
            node = second_first ? first + 1u : first;
            continue;
        }
        if (enter) {
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
    }
    return best;
}
