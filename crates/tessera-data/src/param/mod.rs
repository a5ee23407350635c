//! CPU foundation of the parametric-objects technique (Unterguggenberger et al. 2024, "Fast
//! Rendering of Parametric Objects on Modern GPUs", paper E).
//!
//! * [`sh`]: real spherical harmonics in DIPY's `descoteaux07` and `tournier07` bases.
//! * [`functions`]: the parametric surfaces `f(u, v) -> R³` and their normals; the glyph,
//!   seashell and knit-yarn families live in [`glyph`], [`seashell`] and [`yarn`].
//! * [`lod`]: the PATCH SUBDIVISION stage (paper §4.1), the reference the GPU compute shader is
//!   tested against.
//! * [`scene`]: objects placed by transforms and their bounds; [`scenes`] builds the paper's
//!   curtain and seashell; [`user`] reads users' GLSL functions.

pub mod functions;
pub mod glyph;
pub mod glyph_field;
pub mod lod;
pub mod raytrace;
pub mod reference;
pub mod scene;
pub mod scenes;
pub mod seashell;
pub mod sh;
pub mod split;
pub mod user;
pub mod yarn;

pub use functions::{surface_normal, ParamDomain, ParamFunction};
pub use glyph::{direction_colour, RadiusNormalization, ShGlyph};
pub use lod::{run_lod, LodConfig, LodOutput, Patch, RenderPatch, SplitPattern};
pub use seashell::SeashellParams;
pub use sh::ShBasis;
pub use yarn::{KnitCurve, KnitParams, YarnTube};
