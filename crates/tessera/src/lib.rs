//! Tessera's rendering techniques, one folder each with its shaders beside the Rust that drives
//! it. Data types and CPU references come from `tessera_data`; Vulkan plumbing from
//! `tessera_gpu`.

pub mod bench;
pub mod capacity;
pub mod config;
pub mod error;
pub mod gpu_volume;
pub mod iso;
#[cfg(test)]
mod layout_tests;
pub mod param;
pub mod path;
pub mod raster;
pub mod renderer;
pub mod report;
pub mod scan;
pub mod shaders;
pub mod target;
pub mod tet;
pub mod throughput;

pub use error::{Error, Result};
