//! Ready-made scenes of paper E's benchmarks (§5): the knit "curtain" of Fig. 11 and a seashell
//! (Fig. 12), built from the families of [`super::yarn`] and [`super::seashell`] and placed by
//! transforms.
//!
//! The curtain is one object per loop (per fibre), as the authors' code starts one patch per
//! loop and row: their 235 loops × 254 rows give the paper's "60k yarn curves" (59,690) and, with
//! 6 fibres each, "358k fiber curves" (358,140). Each object spans one loop, `u ∈ [0, 2π]`, and
//! is moved into place: Crane's curve repeats every `2π` shifted by `2π` along x, so loop `k`
//! of a row is the loop at the origin moved by `2πk`, and rows lie `KnitParams::row_offset`
//! apart. Short objects also keep `u` small, so the GPU's f32 sines stay accurate. The fibres'
//! angle `ωt - 2 cos t + φ` does not repeat with the loop unless `ω` is an integer, so the
//! fibres of loop `k` take the phase `φ + 2πkω`, which makes them continue the row's fibres.

use std::f64::consts::TAU;

use glam::{Mat4, Quat, Vec3};

use super::scene::{ParamObject, ParamScene, MAX_OBJECTS};
use super::{KnitCurve, KnitParams, ParamFunction, SeashellParams, YarnTube};
use crate::error::{DataError, Result};

/// Loops per row of the paper's curtain (the authors' `CurtainYarnCurves` object).
pub const PAPER_CURTAIN_LOOPS: u32 = 235;
/// Rows of the paper's curtain.
pub const PAPER_CURTAIN_ROWS: u32 = 254;
/// Fibres per yarn in the authors' fibre objects.
pub const CURTAIN_FIBRES: u32 = 6;
/// Tube radius of a fibre, in Crane's units (the authors' single fibre curve: 0.3).
pub const FIBRE_TUBE_RADIUS: f64 = 0.3;
/// The yarn's colour (the paper's curtain is blue).
pub const CURTAIN_COLOUR: [f32; 3] = [0.25, 0.42, 0.85];
/// The seashell's colour.
pub const SHELL_COLOUR: [f32; 3] = [0.92, 0.78, 0.62];

/// Crane's knit with one loop per object, the curtain's building block.
pub fn curtain_knit() -> KnitParams {
    KnitParams {
        loops: 1,
        ..KnitParams::default()
    }
}

/// The tube radius of a whole yarn: the envelope of its fibre tubes (the authors' single yarn
/// curve: 0.8 = 0.5 + 0.3).
pub fn yarn_tube_radius(knit: &KnitParams) -> f64 {
    knit.yarn_radius + FIBRE_TUBE_RADIUS
}

/// A curtain of `rows` rows of `loops_per_row` loops of Crane's default knit ([`curtain_knit`]),
/// as yarn tubes or as [`CURTAIN_FIBRES`] fibre tubes per yarn; centred on the origin and scaled
/// so that its longer side (width `2π·loops`, height `rows·row_offset`) is 1. Objects are
/// ordered by row, then loop, then fibre.
pub fn yarn_curtain(rows: u32, loops_per_row: u32, fibres: bool) -> Result<ParamScene> {
    yarn_curtain_of(curtain_knit(), rows, loops_per_row, fibres)
}

/// [`yarn_curtain`] of another knit (its `loops` is ignored: each object is one loop).
pub fn yarn_curtain_of(
    knit: KnitParams,
    rows: u32,
    loops_per_row: u32,
    fibres: bool,
) -> Result<ParamScene> {
    let per_loop = if fibres { CURTAIN_FIBRES } else { 1 };
    let count = u64::from(rows) * u64::from(loops_per_row) * u64::from(per_loop);
    if count == 0 || count > MAX_OBJECTS as u64 {
        return Err(DataError::Invalid(format!(
            "a curtain of {rows} rows of {loops_per_row} loops needs 1 to {MAX_OBJECTS} \
             objects, got {count}"
        )));
    }
    let knit = KnitParams { loops: 1, ..knit };
    let width = TAU * f64::from(loops_per_row);
    let height = knit.row_offset() * f64::from(rows);
    let scale = 1.0 / width.max(height);
    let centre = [width * 0.5, knit.row_offset() * f64::from(rows - 1) * 0.5];
    let mut objects = Vec::with_capacity(count as usize);
    for row in 0..rows {
        for k in 0..loops_per_row {
            let offset = [
                TAU * f64::from(k) - centre[0],
                knit.row_offset() * f64::from(row) - centre[1],
            ];
            let place = Mat4::from_scale_rotation_translation(
                Vec3::splat(scale as f32),
                Quat::IDENTITY,
                Vec3::new((offset[0] * scale) as f32, (offset[1] * scale) as f32, 0.0),
            );
            let tubes = if fibres {
                // Phase 2πi/n of fibre i (YarnTube::fibers), advanced by 2πkω for loop k;
                // fract keeps it small and exact for integer twists.
                let turns = (f64::from(k) * knit.twist).fract();
                (0..CURTAIN_FIBRES)
                    .map(|i| {
                        let phase = TAU * (f64::from(i) / f64::from(CURTAIN_FIBRES) + turns);
                        let curve = KnitCurve::Fiber { phase };
                        YarnTube::new(knit, curve, FIBRE_TUBE_RADIUS)
                    })
                    .collect::<std::result::Result<Vec<_>, _>>()
            } else {
                YarnTube::new(knit, KnitCurve::Yarn, yarn_tube_radius(&knit)).map(|t| vec![t])
            }
            .map_err(|e| DataError::Invalid(format!("curtain: {e}")))?;
            objects.extend(tubes.into_iter().map(|t| {
                ParamObject::new(ParamFunction::Yarn(t))
                    .with_transform(place)
                    .with_colour(CURTAIN_COLOUR)
            }));
        }
    }
    Ok(ParamScene::new(objects))
}

/// The paper's curtain, 235 loops × 254 rows: 59,690 yarn tubes or 358,140 fibre tubes.
pub fn paper_curtain(fibres: bool) -> Result<ParamScene> {
    yarn_curtain(PAPER_CURTAIN_ROWS, PAPER_CURTAIN_LOOPS, fibres)
}

/// One seashell, its spiral axis (y) centred on the origin and scaled so that its bounding
/// sphere has radius 1. Paper E's Fig. 12 shell is `SeashellParams::fine_bumps()`.
pub fn seashell(params: SeashellParams) -> Result<ParamScene> {
    params
        .validate()
        .map_err(|e| DataError::Invalid(format!("seashell: {e}")))?;
    let shell = ParamObject::new(ParamFunction::Seashell(params)).with_colour(SHELL_COLOUR);
    let bound = shell.object_radius();
    // The opening's centre lies at height -cos β·R·scale, R = A·exp(θ cot α) running from the
    // domain's start to its end: centre that range.
    let f = f64::from;
    let growth = 1.0 / f(params.alpha_deg).to_radians().tan();
    let spiral = |theta: f32| f(params.spiral_start) * (f(theta) * growth).exp();
    let [start, end] = params.domain().u;
    let axis = f(params.beta_deg).to_radians().cos() * f(params.scale);
    let lift = axis * (spiral(start) + spiral(end)) * 0.5;
    let scale = 1.0 / bound;
    let place = Mat4::from_scale_rotation_translation(
        Vec3::splat(scale),
        Quat::IDENTITY,
        Vec3::new(0.0, lift as f32 * scale, 0.0),
    );
    Ok(ParamScene::new(vec![shell.with_transform(place)]))
}

#[cfg(test)]
#[path = "scenes_tests.rs"]
mod tests;
