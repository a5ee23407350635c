// Shell-to-shell traversal (paper B, Alg. 1) with tet marching (Alg. 2), as
// tessera_data::tet::shell::traverse walks a ray: trace to the exit face of the segment ahead,
// back to its entry face, march the tets between, then go on past the exit for the next
// segment of a non-convex mesh. Tets before t_min are marched but not reported (an eye inside
// the mesh starts at the entry face behind it). The includer defines
//     bool visit_step(uint segment, ShellStep step)
// which receives each tet crossed within [t_min, t_max], clipped to it, and returns false to
// stop the traversal.
// Needs buffers.glsl, params.glsl, ray_space.glsl, bvh.glsl and layout.glsl.

struct ShellStep {
    uint tet;
    float t_enter;
    float t_exit;
    float s_enter;  // the normalized scalar at t_enter and t_exit
    float s_exit;
};

// What one ray's traversal counted (tessera_data's TraversalStats for one ray).
struct TraversalCounts {
    uint segments;
    uint steps;
    uint dead_ends;
    uint step_limits;
    uint backward_steps;
    uint unmatched_exits;
};

bool visit_step(uint segment, ShellStep step);

float infinity() {
    return uintBitsToFloat(0x7f800000u);
}

const uint MARCH_SHELL = 0u;
const uint MARCH_STOPPED = 1u;
const uint MARCH_DEAD_END = 2u;
const uint MARCH_STEP_LIMIT = 3u;

// The exit face of a tet entered through `face` (counter-clockwise about the ray) with fourth
// vertex `apex`: the index of the face vertex opposite it, or 3 when the ray lies in no sector
// (a degenerate or inverted tet). `next` becomes the exit face, apex first, counter-clockwise.
uint exit_face(Projected apex, Projected face[3], out Projected next[3]) {
    bool left[3] = bool[3](ray_left_of(apex, face[0]), ray_left_of(apex, face[1]), ray_left_of(apex, face[2]));
    next = face;
    for (uint i = 0u; i < 3u; ++i) {
        uint j = (i + 1u) % 3u;
        if (left[i] && !left[j]) {
            next = Projected[3](apex, face[i], face[j]);
            return (i + 2u) % 3u;
        }
    }
    return 3u;
}

// Marches one segment from shell face `entry_face` (entered at t_enter); sets `reported` when a
// step within the range reached visit_step.
uint march_segment(RaySpace ray, uint entry_face, float t_enter, float t_min, float t_max, uint segment,
                   inout TraversalCounts counts, out bool reported, out bool stopped) {
    reported = false;
    stopped = false;
    uvec4 shell = shell_faces[entry_face];
    // Outward winding has the entering ray on the right of each edge: reversed, on the left.
    Projected face[3] = Projected[3](project(ray, shell.x), project(ray, shell.z), project(ray, shell.y));
    float s_enter = crossing(face[0], face[1], face[2]).y;
    uint tet = shell.w;
    uint came_from = NO_NEIGHBOUR;
    for (uint step = 0u; step < params.max_steps; ++step) {
        counts.steps += 1u;
        uvec4 ids;
        uvec4 neighbours;
        if (tet >= params.tet_count
            || !tet_decode(tet, came_from, uvec3(face[0].id, face[1].id, face[2].id), ids, neighbours)
            || ids.w >= params.vertex_count) {
            return MARCH_DEAD_END;
        }
        Projected next[3];
        uint opposite = exit_face(project(ray, ids.w), face, next);
        if (opposite == 3u) {
            return MARCH_DEAD_END;
        }
        vec2 leave = crossing(next[0], next[1], next[2]);
        if (leave.x < t_enter) {
            counts.backward_steps += 1u;
        }
        if (t_enter >= t_max) {
            stopped = true;
            return MARCH_STOPPED;
        }
        if (leave.x > t_min) {
            reported = true;
            // The scalar is linear along the stretch: clipping interpolates it.
            float t0 = max(t_enter, t_min);
            float t1 = min(leave.x, t_max);
            float span = leave.x - t_enter;
            float s0 = t0 == t_enter ? s_enter : mix(s_enter, leave.y, (t0 - t_enter) / span);
            float s1 = t1 == leave.x ? leave.y : mix(s_enter, leave.y, (t1 - t_enter) / span);
            if (!visit_step(segment, ShellStep(tet, t0, t1, s0, s1))) {
                stopped = true;
                return MARCH_STOPPED;
            }
        }
        uint across = neighbours[opposite];
        if (across == NO_NEIGHBOUR) {
            return MARCH_SHELL;
        }
        if (across >= params.tet_count) {
            return MARCH_DEAD_END;
        }
        came_from = tet;
        tet = across;
        face = next;
        t_enter = leave.x;
        s_enter = leave.y;
    }
    return MARCH_STEP_LIMIT;
}

// Traverses origin + t dir over [t_min, t_max].
TraversalCounts traverse(vec3 origin, vec3 dir, float t_min, float t_max) {
    TraversalCounts counts = TraversalCounts(0u, 0u, 0u, 0u, 0u, 0u);
    if (!(dot(dir, dir) > 0.0)) {
        return counts;
    }
    RaySpace ray = ray_space(origin, dir);
    uint segment = 0u;
    float floor_t = -infinity();
    float beyond = t_min;
    while (true) {
        ShellHit exit_hit = shell_trace(ray, true, beyond, infinity());
        if (exit_hit.face == NO_FACE) {
            break;
        }
        ShellHit entry = shell_trace(ray, false, floor_t, exit_hit.t);
        // Past the first segment the backward trace stops at the previous exit, so a shell that
        // is not closed cannot send it back into a segment already marched.
        floor_t = exit_hit.t;
        beyond = max(t_min, exit_hit.t);
        if (entry.face == NO_FACE) {
            counts.unmatched_exits += 1u;
            continue;
        }
        if (entry.t >= t_max) {
            break;
        }
#if SHELL_TRACES_ONLY
        // What the traces alone cost: the segment is found, not marched.
        counts.segments += 1u;
        continue;
#endif
        bool reported;
        bool stopped;
        uint end = march_segment(ray, entry.face, entry.t, t_min, t_max, segment, counts, reported, stopped);
        counts.dead_ends += uint(end == MARCH_DEAD_END);
        counts.step_limits += uint(end == MARCH_STEP_LIMIT);
        if (reported) {
            counts.segments += 1u;
            segment += 1u;
        }
        if (stopped) {
            break;
        }
    }
    return counts;
}
