//! Parametric scenes from specs: named surfaces, the paper's curtain and seashell, fields of SH
//! glyphs (procedural or from a coefficient file) and user functions.

use std::path::Path;

use glam::{Mat4, Vec3};

use super::spec::is_user_function;
use super::{LoadOptions, ParamData};
use crate::camera::ViewUp;
use crate::error::{DataError, Result};
use crate::nifti::{load_nifti_components, ComponentVolume};
use crate::param::glyph_field::{sh_glyph_grid, sh_glyph_volume, FieldGlyph};
use crate::param::scene::{ParamObject, ParamScene};
use crate::param::scenes;
use crate::param::user::UserFunction;
use crate::param::{ParamFunction, SeashellParams, ShBasis};

/// Seed of the procedural glyph fields, so that every front end shows the same glyphs.
const GLYPH_SEED: u64 = 1;

impl ParamData {
    /// A GLSL file of a user function (one object over its domain; `options`' ranges override
    /// the file's) or a [`named_scene`] in `options.basis`, [`default_basis`] if unset.
    pub fn load(spec: &str, options: &LoadOptions) -> Result<ParamData> {
        let (scene, user) = if is_user_function(spec) {
            let f = UserFunction::load(Path::new(spec), options.u_range, options.v_range)?;
            let object = ParamObject::new(ParamFunction::User(f.domain));
            (ParamScene::new(vec![object]), Some(f))
        } else {
            let basis = options.basis.unwrap_or_else(|| default_basis(spec));
            let scene = named_scene(spec, basis)?.with_glyph_radius(options.glyph_radius);
            (scene, None)
        };
        Ok(ParamData {
            name: spec.to_string(),
            scene,
            user,
        })
    }
}

/// The basis glyphs of `spec` are in unless told otherwise: DIPY's legacy descoteaux07 for
/// coefficient files (what its fits write by default), descoteaux07 for generated glyphs.
pub fn default_basis(spec: &str) -> ShBasis {
    ShBasis::Descoteaux07 {
        legacy: spec.starts_with("sh:"),
    }
}

/// The scene `spec` names: `param:sphere`, `param:heart`, `param:seashell`,
/// `param:yarn:ROWSxLOOPS[:fibres]` (a knitted curtain; 235x254 is the paper's 59,690 yarn
/// curves), `param:sh-glyph:orderN`, or `param:sh-glyphs:WxH:orderN` (also
/// `procedural:sh-glyphs:…`), glyph scenes scaled into the unit box the other data sets are
/// shown in; or `sh:FILE[:zN]`.
pub fn named_scene(spec: &str, basis: ShBasis) -> Result<ParamScene> {
    if let Some(file) = spec.strip_prefix("sh:") {
        return coefficient_scene(spec, file, basis);
    }
    let rest = spec
        .strip_prefix("param:")
        .or_else(|| spec.strip_prefix("procedural:"))
        .ok_or_else(|| DataError::Invalid(format!("'{spec}' is not a parametric scene")))?;
    let parts: Vec<&str> = rest.split(':').collect();
    let single = |f: ParamFunction| ParamScene::new(vec![ParamObject::new(f)]);
    match parts[..] {
        ["sphere"] => Ok(single(ParamFunction::Sphere)),
        ["heart"] => Ok(single(ParamFunction::Heart)),
        ["seashell"] => scenes::seashell(SeashellParams::default()),
        ["yarn", grid] | ["yarn", grid, "fibres"] => {
            let (rows, loops) = parse_grid(grid, spec, "ROWSxLOOPS")?;
            scenes::yarn_curtain(rows, loops, parts.len() == 3).map_err(|e| e.labelled(spec))
        }
        ["sh-glyph", order] => {
            let order = parse_order(order, spec)?;
            let field =
                sh_glyph_grid(1, 1, order, basis, GLYPH_SEED).map_err(|e| e.labelled(spec))?;
            Ok(single(ParamFunction::ShGlyph(field[0].glyph.clone())))
        }
        ["sh-glyphs", grid, order] => {
            let (nx, ny) = parse_grid(grid, spec, "WxH")?;
            let order = parse_order(order, spec)?;
            let field =
                sh_glyph_grid(nx, ny, order, basis, GLYPH_SEED).map_err(|e| e.labelled(spec))?;
            // The grid spans the unit square; glyphs of min-max radius 1 keep a gap.
            let pitch = 1.0 / nx.max(ny) as f32;
            Ok(glyph_scene(field, pitch, pitch))
        }
        _ => Err(DataError::Invalid(format!(
            "'{spec}': unknown parametric scene (param:sphere, param:heart, param:seashell, \
             param:yarn:ROWSxLOOPS[:fibres], param:sh-glyph:orderN, param:sh-glyphs:WxH:orderN)"
        ))),
    }
}

/// `AxB` of two whole numbers; `form` says what was expected in the error.
fn parse_grid(text: &str, spec: &str, form: &str) -> Result<(u32, u32)> {
    text.split_once('x')
        .and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?)))
        .ok_or_else(|| DataError::Invalid(format!("'{spec}': expected {form}, found '{text}'")))
}

/// The highest SH order a `param:` spec builds glyphs of: every renderer draws it, and the
/// CPU-side tables of a glyph field stay quick to build (checked before any is built).
pub const MAX_SPEC_SH_ORDER: u32 = 16;

/// `orderN`, N even from 2 to [`MAX_SPEC_SH_ORDER`].
fn parse_order(text: &str, spec: &str) -> Result<u32> {
    text.strip_prefix("order")
        .and_then(|n| n.parse().ok())
        .filter(|&n: &u32| n.is_multiple_of(2) && (2..=MAX_SPEC_SH_ORDER).contains(&n))
        .ok_or_else(|| {
            DataError::Invalid(format!(
                "'{spec}': expected orderN (even N, 2 to {MAX_SPEC_SH_ORDER}), found '{text}'"
            ))
        })
}

/// Glyphs of an SH coefficient volume: `sh:FILE` (every voxel) or `sh:FILE:zN` (slice N).
fn coefficient_scene(spec: &str, file: &str, basis: ShBasis) -> Result<ParamScene> {
    // A `:z` that is not followed by a number belongs to the file name.
    let (file, slice) = match file.rsplit_once(":z") {
        Some((f, z)) if z.parse::<u32>().is_ok() => (f, z.parse::<u32>().ok()),
        _ => (file, None),
    };
    let volume = load_nifti_components(Path::new(file))?;
    glyph_field_scene(&volume, basis, slice, file).map_err(|e| e.labelled(spec))
}

/// The glyphs of a coefficient volume (of slice `z_slice` only, if given) as a scene: placed
/// by the voxel spacing, the longest side of the volume spanning the unit box, each as wide as
/// the finest voxel side lets glyphs of the grid be; the view up from the volume's
/// orientation. `what` names the data in errors.
pub fn glyph_field_scene(
    volume: &ComponentVolume,
    basis: ShBasis,
    z_slice: Option<u32>,
    what: &str,
) -> Result<ParamScene> {
    if volume.spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
        return Err(DataError::Invalid(format!(
            "{what}: spacing {:?} must be positive along every axis",
            volume.spacing
        )));
    }
    let field = sh_glyph_volume(volume, basis, z_slice, what)?;
    let sides = Vec3::from(volume.dims.map(|d| d as f32)) * Vec3::from(volume.spacing);
    let scale = 1.0 / sides.max_element();
    let finest = volume.spacing.into_iter().fold(f32::INFINITY, f32::min);
    let mut scene = glyph_scene(field, scale, finest * scale);
    scene.up = ViewUp::towards_head(volume.up_axis());
    Ok(scene)
}

/// Glyphs at their centres times `scale`, of radius 0.45 `pitch` (min-max radius 1): a gap
/// stays between neighbours `pitch` apart.
fn glyph_scene(field: Vec<FieldGlyph>, scale: f32, pitch: f32) -> ParamScene {
    let objects = field
        .into_iter()
        .map(|g| {
            let to_world = Mat4::from_translation(g.centre * scale)
                * Mat4::from_scale(Vec3::splat(0.45 * pitch));
            ParamObject::new(ParamFunction::ShGlyph(g.glyph)).with_transform(to_world)
        })
        .collect();
    ParamScene::new(objects)
}

#[cfg(test)]
#[path = "param_spec_tests.rs"]
mod tests;
