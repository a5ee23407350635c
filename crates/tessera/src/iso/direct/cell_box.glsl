// The box of a block's cells that made triangles at an isovalue, packed in 32 bits: its first
// and last cell, local to the block (CELL_BOX_BITS per coordinate), and CELL_BOX_VALID (both
// defines from iso::direct::cell_boxes). The extraction writes it beside the isovalue's
// bits; the occlusion test uses it in place of the block's whole box when the isovalue is the
// same, as every triangle the block makes at that isovalue lies in it.
#ifndef ISO_DIRECT_CELL_BOX_GLSL
#define ISO_DIRECT_CELL_BOX_GLSL

const uint CELL_BOX_MASK = (1u << CELL_BOX_BITS) - 1u;

uint cell_box_pack(uvec3 lo, uvec3 hi) {
    uint packed = CELL_BOX_VALID;
    for (uint a = 0u; a < 3u; ++a) {
        packed |= lo[a] << (a * CELL_BOX_BITS);
        packed |= hi[a] << ((a + 3u) * CELL_BOX_BITS);
    }
    return packed;
}

void cell_box_unpack(uint packed, out uvec3 lo, out uvec3 hi) {
    for (uint a = 0u; a < 3u; ++a) {
        lo[a] = (packed >> (a * CELL_BOX_BITS)) & CELL_BOX_MASK;
        hi[a] = (packed >> ((a + 3u) * CELL_BOX_BITS)) & CELL_BOX_MASK;
    }
}

// Narrows the grid range [lo, hi] of a block (its first and last sample) to the cells of
// `recorded` (the block's packed box and the bits of the isovalue it was made at) when it was
// made at `iso`.
void cell_box_narrow(uvec2 recorded, float iso, inout uvec3 lo, inout uvec3 hi) {
    if ((recorded.x & CELL_BOX_VALID) != 0u && recorded.y == floatBitsToUint(iso)) {
        uvec3 first;
        uvec3 last;
        cell_box_unpack(recorded.x, first, last);
        hi = min(lo + last + 1u, hi);
        lo = lo + first;
    }
}

#endif
