//! Isosurface techniques over regular volumes (papers C and D and their references).

pub mod minmax;
pub mod raymarch;
