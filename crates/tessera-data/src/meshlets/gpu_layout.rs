//! The layout the GPU paths (mesh-shader and compute, `tessera::iso::meshlets`) write the same
//! meshlets in, so that a readback is a [`super::MeshletMesh`] and compares with
//! [`super::extract_meshlets`] meshlet for meshlet. Nothing here runs; it is the contract the
//! shaders follow.
//!
//! # Buffers (std430, 4-byte words)
//!
//! | buffer | content |
//! |---|---|
//! | `counters` | `uint meshlets, vertices, triangles, overflow`: totals reserved with `atomicAdd`; the totals keep counting past the capacities, `overflow` gets bit 0, and the host grows the buffers and extracts again (never a silent truncation); bit 1 says an extraction counted otherwise than its analysis (a defect, reported as an error) |
//! | `meshlets` | [`super::Meshlet`] as declared (`#[repr(C)]`, 11 words, stride 44 bytes): in GLSL with `float[3]`/`uint[2]` members, never `vec3`, whose std430 alignment of 16 would pad it |
//! | `positions`, `normals` | `float[]`, three per vertex, as `Vec<[f32; 3]>` |
//! | `local_indices` | `uint[]` holding the bytes of [`super::MeshletMesh::local_indices`] |
//! | `block_meshlets` | per entry of the compacted occupied-block list: `uint first_meshlet, meshlet_count`, for culling a block's meshlets by its implicit box at once |
//!
//! `local_indices` is written a byte at a time by different workgroups, so no two meshlets
//! may share a word: the GPU reserves triangles in multiples of 4 (12 bytes, 3 words), which
//! leaves up to 3 unused triangles of zeros between meshlets. `triangle_offset` and
//! `triangle_count` stay exact, so the readback is a valid `MeshletMesh` with gaps, and
//! [`super::MeshletMesh::triangles`] skips them.
//!
//! # Order
//!
//! One reservation per block (meshlets, vertices, triangles of all its subblocks, made by the
//! region analysis), so a block's meshlets are contiguous and, inside the block, in the CPU
//! reference's order: subblocks in Morton order; in a meshlet, vertices as
//! [`super::subblock::SubblockSurface::edges`] orders them (edges owned by occupied core
//! cells in Morton order, x, y, z edge each, then those of padding cells x fastest over the
//! subblock's box), triangles by occupied core cell in Morton order, each cell's in table
//! order. Only the order of blocks depends on scheduling, so sorting meshlets by
//! `(block_origin, subblock_origin)` makes the GPU's output and the CPU's equal bit for bit;
//! the mesh-shader and compute paths are compared the same way.
//!
//! # Region analysis → extraction (task payload, or shared memory on the compute path)
//!
//! One workgroup per occupied block first reads the block's samples with a one-sample apron
//! into shared memory. On the task path (32 invocations, the paper's) invocation `i`
//! classifies the cells with Morton codes `8i .. 8i + 8` (a 2×2×2 subblock, an eighth); on the
//! compute path (128) four invocations share each eighth. Each eighth's triangles, occupied
//! cells and the crossed edges they and their padding points own are summed in shared memory;
//! sums over 8 and 32 consecutive eighths give the 4×4×4 and 8×8×4 candidates. Shared-memory
//! sums rather than subgroup operations, since the subgroup size may be smaller than 32 (8 on
//! lavapipe). The payload per block:
//!
//! * `uint block`: index into the occupied-block list;
//! * `uint base_meshlet, base_vertex, base_triangle`: the block's reservation;
//! * per subblock (at most 32), four words of 16-bit halves: `first_code, code_count`; its
//!   vertex and triangle offsets within the block's reservation; its vertex and triangle
//!   counts as the analysis made them (the extraction checks its own against them); the
//!   range of its occupied cells in `cells`;
//! * `uint8 cells[256]`: Morton codes of occupied core cells, subblock after subblock (at
//!   most [`super::MAX_OCCUPIED_CELLS`] per subblock, 256 per block).
//!
//! Padding points are not listed: the extraction workgroup re-tests the at most
//! 9·9·5 − 8·8·4 = 149 points beyond a subblock's max faces (fewer for smaller subblocks),
//! from the samples it holds (a mesh workgroup loads its subblock's), which keeps the payload
//! within 1 KiB.
