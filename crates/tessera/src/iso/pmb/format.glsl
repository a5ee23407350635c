// The PMB output's records, as the extraction writes them and the draws read them.

#ifndef PMB_FORMAT_GLSL
#define PMB_FORMAT_GLSL

// tessera_data::pmb::PmbBlock, scalar arrays so std430 packs it in 7 words.
struct PmbBlock {
    uint block[3];
    uint first_vertex;
    uint vertex_count;
    uint first_index;
    uint triangle_count;
};

// Blocks with triangles, vertices and triangles reserved so far (they keep counting past the
// capacities), and whether a reservation did not fit.
struct PmbCounters {
    uint blocks;
    uint vertices;
    uint triangles;
    uint overflow;
};

#endif
