// The buffers every meshlet extraction pass binds, in one layout (tessera_data::meshlets::
// gpu_layout describes their content; host side: iso::meshlets::buffers).
// Needs iso/direct/block_list.glsl.

#include "iso/meshlets/format.glsl"

layout(binding = 0) uniform VOLUME_SAMPLER volume_tex;
layout(binding = 1) readonly buffer Blocks { BlockListHeader block_header; uint occupied_blocks[]; };
layout(binding = 2) coherent buffer Counters { MeshletCounters counters; };
layout(binding = 3) writeonly buffer Meshlets { Meshlet meshlets[]; };
layout(binding = 4) writeonly buffer Positions { float positions[]; };
layout(binding = 5) writeonly buffer Normals { float normals[]; };
// Three local indices per triangle, a byte each, four to a word.
layout(binding = 6) writeonly buffer LocalIndices { uint local_index_words[]; };
// Per entry of the occupied-block list: first meshlet, meshlet count.
layout(binding = 7) writeonly buffer BlockMeshlets { uvec2 block_meshlets[]; };
