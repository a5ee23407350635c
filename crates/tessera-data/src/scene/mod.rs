//! The data behind one front door: what a data spec (a file path, or `procedural:…`,
//! `tets:…`, `param:…`, `sh:…`) names, loaded into a [`Dataset`], and the [`Appearance`]
//! options that change how it looks without changing it. The rules here used to live in the
//! command line; keeping them beside the data lets every front end (CLI, benchmarks, tests)
//! agree on what a spec means without a GPU.
//!
//! * [`spec`]: which kind of data a spec names, volumes and tet meshes from specs, the bytes
//!   a volume will need before it is read.
//! * [`param_spec`]: parametric scenes from specs.
//! * [`appearance`]: isovalue, integrand, transfer function, background.
//! * [`parse`]: the option texts (triples, sizes, ranges, colours) as value parsers.

pub mod appearance;
pub mod param_spec;
pub mod parse;
pub mod spec;

pub use appearance::{Appearance, IntegrandChoice, ResolvedIntegrand};
pub use param_spec::{default_basis, glyph_field_scene, named_scene};
pub use spec::{expected_volume_bytes, load_volume_spec};

use crate::camera::ViewUp;
use crate::error::Result;
use crate::param::scene::ParamScene;
use crate::param::user::UserFunction;
use crate::param::{RadiusNormalization, ShBasis};
use crate::raw::RawOptions;
use crate::tet::{MeshReport, TetMesh};
use crate::volume::Volume;

/// A loaded data set of any kind.
#[derive(Debug, Clone)]
pub enum Dataset {
    Volume(Volume),
    Tets(TetData),
    Param(ParamData),
}

/// The three families of data, each drawn by its own techniques.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DataKind {
    Volume,
    Tets,
    Param,
}

impl DataKind {
    /// The kind in words, plural, for messages ("technique 'raymarch' draws volumes").
    pub fn describe(self) -> &'static str {
        match self {
            DataKind::Volume => "volumes",
            DataKind::Tets => "tetrahedral meshes",
            DataKind::Param => "parametric objects",
        }
    }
}

/// A tetrahedral mesh and how it was made.
#[derive(Debug, Clone)]
pub struct TetData {
    /// The spec it was loaded from, for messages.
    pub name: String,
    pub mesh: TetMesh,
    /// `tets:asteroids:` field: one bounding tet per asteroid, sphere-traced.
    pub asteroids: bool,
    /// What validation fixed, for meshes read from files.
    pub report: Option<MeshReport>,
}

/// A parametric scene, and the user's function when its one object is one.
#[derive(Debug, Clone)]
pub struct ParamData {
    /// The spec it was loaded from, for messages.
    pub name: String,
    pub scene: ParamScene,
    pub user: Option<UserFunction>,
}

/// What loading needs besides the spec.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// How to read raw volume files (NRRD and NIfTI use only the NaN policy).
    pub raw: RawOptions,
    /// SH basis of glyph scenes; `None` = [`default_basis`] of the spec.
    pub basis: Option<ShBasis>,
    /// How glyph scenes map each glyph's SH values to its radius (min-max by default, as DIPY).
    pub glyph_radius: RadiusNormalization,
    /// Parameter ranges of a user function, overriding the file's `// u:` / `// v:` lines.
    pub u_range: Option<[f32; 2]>,
    pub v_range: Option<[f32; 2]>,
}

impl Dataset {
    /// Loads what `spec` names ([`DataKind::of_spec`] decides which loader reads it). Errors
    /// name the spec or the file.
    pub fn load(spec: &str, options: &LoadOptions) -> Result<Dataset> {
        Ok(match DataKind::of_spec(spec) {
            DataKind::Volume => Dataset::Volume(load_volume_spec(spec, &options.raw)?),
            DataKind::Tets => Dataset::Tets(TetData::load(spec)?),
            DataKind::Param => Dataset::Param(ParamData::load(spec, options)?),
        })
    }

    /// A volume's own name (e.g. `head_256x256x256_uint8`); the spec of other data.
    pub fn name(&self) -> &str {
        match self {
            Dataset::Volume(v) => v.name(),
            Dataset::Tets(t) => &t.name,
            Dataset::Param(p) => &p.name,
        }
    }

    pub fn kind(&self) -> DataKind {
        match self {
            Dataset::Volume(_) => DataKind::Volume,
            Dataset::Tets(_) => DataKind::Tets,
            Dataset::Param(_) => DataKind::Param,
        }
    }

    /// The view up the data asks for: towards the head where a medical file names an
    /// anatomical space; `None` where it says nothing.
    pub fn view_up(&self) -> Option<ViewUp> {
        match self {
            Dataset::Volume(v) => ViewUp::towards_head(v.up_axis()),
            Dataset::Tets(_) => None,
            Dataset::Param(p) => p.scene.up,
        }
    }
}

#[cfg(test)]
mod tests;
