//! Isosurfaces as meshlets (paper C, "Real-Time Meshlet Extraction from Scalar Volumes"):
//! the meshlet format shared by every producer and consumer, and the CPU references the GPU
//! paths are tested against.
//!
//! | file | job |
//! |---|---|
//! | `format` | [`Meshlet`], [`MeshletMesh`], the limits, validation, placement |
//! | `morton` | Morton order of the cells of an 8×8×4 block |
//! | `subblock` | a candidate subblock, its PMB vertex ownership and counts |
//! | `partition` | region analysis: a block into subblocks that each fit a meshlet |
//! | `extract` | the extraction: occupied blocks → partitions → meshlets |
//! | `offline` | meshoptimizer meshlets of a welded mesh |
//! | `file` | the meshlet file `extract --meshlets` writes, and its reader |
//! | `gpu_layout` | (documentation only) the buffers and order the GPU paths will write |

pub mod extract;
pub mod file;
pub mod format;
pub mod gpu_layout;
pub mod morton;
pub mod offline;
pub mod partition;
pub mod subblock;

pub use extract::{check_meshlet_dims, extract_meshlets, extract_meshlets_physical};
pub use file::{read_meshlet_file, write_meshlet_file, MeshletFile, MeshletUnits};
pub use format::{
    Meshlet, MeshletMesh, MAX_CELLS_PER_AXIS, MAX_OCCUPIED_CELLS, MAX_TRIANGLES, MAX_VERTICES,
};
pub use offline::offline_meshlets;

#[cfg(test)]
mod extract_tests;
#[cfg(test)]
mod file_tests;
#[cfg(test)]
mod format_tests;
#[cfg(test)]
mod morton_tests;
#[cfg(test)]
mod offline_tests;
#[cfg(test)]
mod partition_tests;
