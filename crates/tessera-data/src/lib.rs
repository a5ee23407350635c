//! Tessera's data model and CPU reference algorithms. Nothing here knows about Vulkan:
//! file formats, procedural generators, cameras and the reference implementations the GPU
//! techniques are tested against.

pub mod camera;
mod clusters;
pub mod error;
pub mod facing;
pub mod histogram;
pub mod image;
pub mod input;
pub mod load;
pub mod marching_cubes;
pub mod mc_ambiguity;
pub mod mc_tables;
pub mod mesh;
pub mod mesh_read;
#[cfg(test)]
mod mesh_read_tests;
pub mod meshlets;
pub mod minmax;
pub mod nifti;
pub mod nrrd;
pub mod orientation;
pub mod param;
pub mod pmb;
pub mod procedural;
pub mod rasterize;
pub mod raw;
pub mod raycast;
mod sample_data;
pub mod scene;
pub mod shading;
pub mod sniff;
#[cfg(test)]
mod test_files;
#[cfg(test)]
mod test_volumes;
pub mod tet;
pub mod transfer;
pub mod view;
pub mod volume;
pub mod vti;
mod vtk_xml;

pub use camera::{GridCamera, GridFrame, OrbitCamera, Projection, ViewUp};
pub use error::DataError;
pub use image::RgbaImage;
pub use orientation::{AnatomicalSpace, Orientation, OrientationSource};
pub use view::{DepthFit, View};
pub use volume::{IsoValue, NanPolicy, Samples, ScalarType, Volume};

#[cfg(test)]
mod robustness_tests;
