// Stages an extraction may leave out for performance work (tessera::iso::ablation, set by the
// host as EXTRACTION_ABLATION; absent: the whole extraction).
#ifndef EXTRACTION_ABLATION
#define EXTRACTION_ABLATION 0
#endif
#define ABLATION_ANALYSIS_ONLY 1
#define ABLATION_NO_VERTEX_ARITHMETIC 2
