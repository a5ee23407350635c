//! Techniques for tetrahedral meshes (paper A and B).

pub mod interval;
pub mod shell;
