//! What changes how data looks without changing the data: the isovalue of a volume, what rays
//! accumulate through a tet mesh, and the background. Each rule the front ends share (the auto
//! integrand, the default background of each kind of data) lives here once.

use super::{DataKind, TetData};
use crate::error::{DataError, Result};
use crate::shading;
use crate::tet::scalar_integral::mapping_range;
use crate::tet::TetMesh;
use crate::transfer::{IntegrandTable, ScalarMode, TransferFunction, TABLE_KNOTS};
use crate::volume::{IsoValue, Volume};

/// Light behind a tet mesh, which absorbs it on the way to the eye.
pub const BACKLIGHT: [f32; 3] = [1.0, 0.97, 0.9];
/// Behind emitting meshes, maximum projections and asteroids, which light themselves.
pub const DARK: [f32; 3] = [0.02, 0.02, 0.03];
/// Behind parametric scenes.
pub const PARAM_BACKGROUND: [f32; 3] = [0.1, 0.1, 0.12];
/// Behind isosurfaces: the iso techniques clear to [`shading::BACKGROUND`] (a shader define),
/// whatever a front end asks for.
pub const VOLUME_BACKGROUND: [f32; 3] = [
    shading::BACKGROUND[0],
    shading::BACKGROUND[1],
    shading::BACKGROUND[2],
];

/// What rays accumulate through a tet mesh, as asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntegrandChoice {
    /// Scalar absorption when the mesh has vertex scalars and no per-tet colours, else
    /// tet absorption.
    Auto,
    /// Per-tet absorption colours (white where the mesh has none).
    TetAbsorption,
    /// The vertex scalars through the transfer function.
    Scalar(ScalarMode),
}

impl IntegrandChoice {
    /// `auto`, `tet-absorption`, or a [`ScalarMode`] (`absorption`, `emission`, `mip`).
    pub fn parse(text: &str) -> Result<IntegrandChoice> {
        match text {
            "auto" => Ok(IntegrandChoice::Auto),
            "tet-absorption" => Ok(IntegrandChoice::TetAbsorption),
            _ => ScalarMode::parse(text)
                .map(IntegrandChoice::Scalar)
                .map_err(|_| {
                    DataError::Invalid(format!(
                        "integration '{text}': choose auto, tet-absorption, absorption, \
                         emission or mip"
                    ))
                }),
        }
    }
}

/// What rays accumulate through a particular mesh, with everything the renderer needs.
#[derive(Debug, Clone, PartialEq)]
pub enum ResolvedIntegrand {
    TetAbsorption,
    /// No integral: the asteroid inside each bounding tet, sphere-traced.
    Asteroids,
    Scalar {
        mode: ScalarMode,
        table: IntegrandTable,
        /// The scalar range mapped onto the table (the one asked for, or the mesh's own).
        range: (f32, f32),
    },
}

impl ResolvedIntegrand {
    /// A few words for a report line, e.g. `absorption of 'temperature'`.
    pub fn describe(&self, mesh: &TetMesh) -> String {
        match self {
            ResolvedIntegrand::TetAbsorption => "tet absorption".to_string(),
            ResolvedIntegrand::Asteroids => "sphere-traced asteroids".to_string(),
            ResolvedIntegrand::Scalar { mode, .. } => {
                format!("{mode:?} of '{}'", mesh.scalar_name).to_lowercase()
            }
        }
    }
}

/// How data is shown. The defaults are the command line's.
#[derive(Debug, Clone, PartialEq)]
pub struct Appearance {
    /// Isosurface of a volume.
    pub iso: IsoValue,
    pub integrand: IntegrandChoice,
    /// Transfer function of scalar integrands.
    pub transfer: TransferFunction,
    /// Absorption or emission per unit length at full opacity (the mesh's longest side is 1).
    pub density: f32,
    /// Scalar range mapped onto the transfer function (default: the mesh's own).
    pub range: Option<(f32, f32)>,
    /// One absorption colour for every tet, in place of the mesh's per-tet colours.
    pub absorption: Option<[f32; 3]>,
    /// `None` = the data's default ([`Appearance::background`]).
    pub background: Option<[f32; 3]>,
}

impl Default for Appearance {
    fn default() -> Self {
        Appearance {
            iso: IsoValue::Normalized(0.5),
            integrand: IntegrandChoice::Auto,
            transfer: TransferFunction::preset("cool-warm").expect("cool-warm is built in"),
            density: 4.0,
            range: None,
            absorption: None,
            background: None,
        }
    }
}

fn finite_iso(value: f32) -> Result<f32> {
    if !value.is_finite() {
        return Err(DataError::Invalid(format!(
            "isovalue {value} is not a finite number"
        )));
    }
    Ok(value)
}

impl Appearance {
    /// The isovalue in the volume's texel space.
    pub fn iso_texel(&self, volume: &Volume) -> Result<f32> {
        finite_iso(volume.iso_to_texel(self.iso))
    }

    /// The isovalue for a volume whose texel values span `value_range` (texels are the raw
    /// sample values), so a renderer can re-resolve it without the volume.
    pub fn iso_in_range(&self, value_range: (f32, f32)) -> Result<f32> {
        finite_iso(self.iso.in_range(value_range))
    }

    /// The integrand for `tets`: asteroids are always sphere-traced; `auto` integrates the
    /// scalars by absorption unless the mesh has none or brings (or is given) its own colours.
    pub fn resolve_integrand(&self, tets: &TetData) -> Result<ResolvedIntegrand> {
        if tets.asteroids {
            return Ok(ResolvedIntegrand::Asteroids);
        }
        let mesh = &tets.mesh;
        let coloured = self.absorption.is_some() || mesh.absorption.is_some();
        let mode = match self.integrand {
            IntegrandChoice::TetAbsorption => None,
            IntegrandChoice::Auto if mesh.scalars.is_none() || coloured => None,
            IntegrandChoice::Auto => Some(ScalarMode::Absorption),
            IntegrandChoice::Scalar(mode) => Some(mode),
        };
        let Some(mode) = mode else {
            return Ok(ResolvedIntegrand::TetAbsorption);
        };
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(DataError::Invalid(format!(
                "--density must be a positive number, not {}",
                self.density
            )));
        }
        let range = mapping_range(mesh, self.range, &tets.name)?;
        let table = IntegrandTable::new(&self.transfer, mode, self.density, TABLE_KNOTS);
        Ok(ResolvedIntegrand::Scalar { mode, table, range })
    }

    /// Gives every tet the one absorption colour, if one is set; the GPU upload reads the
    /// colours from the mesh.
    pub fn apply_absorption(&self, mesh: &mut TetMesh) {
        if let Some(colour) = self.absorption {
            mesh.absorption = Some(vec![colour; mesh.tets.len()]);
        }
    }

    /// The background asked for, or the data's own: light behind absorbing meshes, dark behind
    /// what emits, [`PARAM_BACKGROUND`] and [`VOLUME_BACKGROUND`] for the other kinds.
    pub fn background(&self, kind: DataKind, integrand: Option<&ResolvedIntegrand>) -> [f32; 3] {
        if let Some(colour) = self.background {
            return colour;
        }
        match kind {
            DataKind::Volume => VOLUME_BACKGROUND,
            DataKind::Param => PARAM_BACKGROUND,
            DataKind::Tets => match integrand {
                Some(ResolvedIntegrand::Asteroids)
                | Some(ResolvedIntegrand::Scalar {
                    mode: ScalarMode::Emission | ScalarMode::Maximum,
                    ..
                }) => DARK,
                _ => BACKLIGHT,
            },
        }
    }
}

#[cfg(test)]
#[path = "appearance_tests.rs"]
mod tests;
