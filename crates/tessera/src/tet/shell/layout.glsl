// The compact tet layouts of tessera_data::tet::shell (Tet32, Tet20, Tet16; TET_LAYOUT picks
// one), decoded as `TetLayout::decode` decodes them: the tet entered through the face with
// vertex ids `entered`, from tet `came_from` (NO_NEIGHBOUR from the shell), yields its four
// vertices (the entered face's, then the fourth from the XOR field) and the tet across the
// face opposite each. False where the layout can tell the face is not the tet's (Tet32 only).
// Needs buffers.glsl.

uint tet_word(uint tet, uint word) {
    return tet_words[tet * uint(TET_WORDS) + word];
}

// Rank of ids[i] among the four (ascending, equal ids ranked by position).
uint rank_of(uvec4 ids, uint i) {
    uint rank = 0u;
    for (uint j = 0u; j < 4u; ++j) {
        rank += uint(ids[j] < ids[i] || (ids[j] == ids[i] && j < i));
    }
    return rank;
}

bool tet_decode(uint tet, uint came_from, uvec3 entered, out uvec4 vertices, out uvec4 neighbours) {
    neighbours = uvec4(NO_NEIGHBOUR);
    vertices = uvec4(entered, 0u);
#if TET_LAYOUT == TET_LAYOUT_TET32
    // v0 v1 v2 vx n0 n1 n2 n3: neighbours in the stored vertex order.
    uvec3 v = uvec3(tet_word(tet, 0u), tet_word(tet, 1u), tet_word(tet, 2u));
    uint vx = tet_word(tet, 3u);
    uvec4 own = uvec4(v, vx ^ v.x ^ v.y ^ v.z);
    vertices.w = vx ^ entered.x ^ entered.y ^ entered.z;
    for (uint i = 0u; i < 4u; ++i) {
        uint at = 4u;
        for (uint k = 3u; k < 4u; --k) {
            at = own[k] == vertices[i] ? k : at;
        }
        if (at == 4u) {
            return false;
        }
        neighbours[i] = tet_word(tet, 4u + at);
    }
#elif TET_LAYOUT == TET_LAYOUT_TET20
    // vx n0 n1 n2 n3: neighbours by the rank of their opposite vertex.
    vertices.w = tet_word(tet, 0u) ^ entered.x ^ entered.y ^ entered.z;
    for (uint i = 0u; i < 4u; ++i) {
        neighbours[i] = tet_word(tet, 1u + rank_of(vertices, i));
    }
#else
    // vx nx0 nx1 nx2 with nx[j] = n[j] ^ n[3]: the tet came from recovers n[3].
    vertices.w = tet_word(tet, 0u) ^ entered.x ^ entered.y ^ entered.z;
    uint entered_rank = rank_of(vertices, 3u);
    uint last = entered_rank == 3u ? came_from : tet_word(tet, 1u + entered_rank) ^ came_from;
    for (uint i = 0u; i < 4u; ++i) {
        uint r = rank_of(vertices, i);
        neighbours[i] = r == 3u ? last : tet_word(tet, 1u + r) ^ last;
    }
#endif
    return true;
}
