// Invocations of a subgroup taking turns: a ballot of those that have work for the whole
// subgroup, then each in turn, lowest first, while the subgroup does that work together. The
// includer enables GL_KHR_shader_subgroup_ballot.
//
//   uvec4 pending = subgroupBallot(has_work);
//   while (subgroup_turns_left(pending)) {
//       uint lane = subgroup_next_turn(pending);
//       ... subgroupShuffle(x, lane) ...
//   }

#ifndef COMMON_SUBGROUP_TURNS_GLSL
#define COMMON_SUBGROUP_TURNS_GLSL

// Whether any invocation of the ballot `pending` still waits for its turn.
bool subgroup_turns_left(uvec4 pending) {
    return any(notEqual(pending, uvec4(0u)));
}

// The lowest invocation of `pending`, taken out of it.
uint subgroup_next_turn(inout uvec4 pending) {
    uint lane = subgroupBallotFindLSB(pending);
    pending[lane / 32u] &= ~(1u << (lane % 32u));
    return lane;
}

#endif
