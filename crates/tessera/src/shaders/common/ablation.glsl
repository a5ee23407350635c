// Stages an extraction may leave out for performance work (tessera::iso::ablation, set by the
// host as EXTRACTION_ABLATION; absent: the whole extraction).
#ifndef EXTRACTION_ABLATION
#define EXTRACTION_ABLATION 0
#endif
#define ABLATION_ANALYSIS_ONLY 1
#define ABLATION_NO_VERTEX_ARITHMETIC 2
#define ABLATION_SAMPLES_ONLY 3

// The no-vertex-arithmetic ablation's stand-in for an edge vertex: the edge's start and a fixed
// normal. Returns whether it stands in; a constant, so the arithmetic it guards is compiled out
// where it does.
bool ablation_stands_in_for_vertex(uvec3 start, out vec3 position, out vec3 normal) {
    position = vec3(start);
    normal = vec3(0.0, 0.0, 1.0);
    return EXTRACTION_ABLATION == ABLATION_NO_VERTEX_ARITHMETIC;
}
