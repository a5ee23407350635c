//! Isosurfaces as Parallel Marching Blocks extracts them (Liu et al., paper C's real-time
//! reference): per block of cells, one vertex per crossed grid edge of the block's closed box
//! and triangles as 16-bit indices local to the block. The format here is what the GPU
//! extraction (`tessera::iso::pmb`) reads back; it is plain data so tests and exports need no
//! device.
//!
//! | file | job |
//! |---|---|
//! | `block_size` | [`PmbBlockSize`], the block shapes and the vertex bound that keeps indices 16-bit |
//! | `mesh` | [`PmbBlock`], [`PmbMesh`]: validation, triangles in global positions, welding |

pub mod block_size;
pub mod mesh;

pub use block_size::PmbBlockSize;
pub use mesh::{PmbBlock, PmbMesh};

#[cfg(test)]
mod mesh_tests;
