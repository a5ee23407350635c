//! SH glyphs as parametric surfaces (paper E §3, §5 "SH Glyphs"): a sphere whose radius in
//! direction `d(θ, φ)` is the SH expansion `r(d) = Σ_j c_j Y_j(d)`, i.e.
//! `f(u, v) = r(d(u, v)) · d(u, v)` with `u = θ ∈ [0, π]` (polar angle from +z) and
//! `v = φ ∈ [0, 2π]` (azimuth), `d = (sin u cos v, sin u sin v, cos u)` as in [`super::sh`].
//!
//! Radius normalisation. Paper E itself does not normalise: its shader places the point at
//! `to_sphere(u, v, r)` with the raw, possibly negative `r` (a negative lobe passes through the
//! centre and appears on the opposite side). dMRI glyph displays usually min-max normalise each
//! glyph instead (DIPY's `minmax_normalize` in `dipy/reconst/odf.py`: `(r - min) / (max - min)`
//! over the sphere), which makes glyphs of different voxels comparable in size and never
//! inverted, but lifts every direction by `-min` where the ODF dips below zero. `MaxAbs`
//! keeps shapes instead: `r / max|r|`, where a negative lobe passes through the centre. The SH
//! orders drawn here are even, so `r(-d) = r(d)` and that lobe lands where `|r|` points: the
//! glyph is the surface of `|r| / max|r|` (what the ray tracer's squared implicit form draws
//! too). `PositiveLobes` draws `max(r, 0) / max r`: negative lobes vanish. Every mapping is offered ([`RadiusNormalization`]); the extremes are estimated once
//! per glyph on a fixed direction grid.
//!
//! Colour by direction: the glyph shader of paper E's code colours a surface point by the
//! absolute components of its unit direction from the glyph centre, RGB = `(|x|, |y|, |z|)`, in
//! the SH frame (it swaps y/z only because its world is y-up); see [`direction_colour`].

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::sh::{check_coefficients, evaluate_unchecked, ShBasis};
use crate::error::Result;

/// How the raw SH radius is mapped to the glyph radius.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum RadiusNormalization {
    /// `r` as is (paper E's shader); negative values flip through the centre.
    Raw,
    /// `(r - r_min) / (r_max - r_min)`, clamped to `[0, 1]` (DIPY's `minmax_normalize`); an
    /// isotropic glyph (`r_max == r_min`) becomes the unit sphere.
    #[default]
    MinMax,
    /// `r / max|r|`; an all-zero glyph stays a point.
    MaxAbs,
    /// `max(r, 0) / max r`: directions where the ODF is negative get no radius (the negative
    /// lobes vanish); a glyph with no positive value is a point.
    PositiveLobes,
}

/// One SH glyph: validated coefficients plus its normalisation.
#[derive(Debug, Clone, PartialEq)]
pub struct ShGlyph {
    basis: ShBasis,
    order: u32,
    coeffs: Vec<f64>,
    normalization: RadiusNormalization,
    raw_min: f64,
    raw_max: f64,
}

impl ShGlyph {
    /// Validates `coeffs` against `order` (even, `(L+1)(L+2)/2` finite values) and, unless
    /// `normalization` is `Raw`, estimates the radius extremes on a `(8L+17) × (16L+32)` grid
    /// of (θ, φ) that includes both poles. A band-limited function of order `L` cannot vary much
    /// between grid points that are `π/(8L)` apart, so the estimate is within a small fraction of
    /// the true range; normalised radii are clamped so that the residual never inverts a glyph.
    pub fn new(
        basis: ShBasis,
        order: u32,
        coeffs: Vec<f64>,
        normalization: RadiusNormalization,
    ) -> Result<ShGlyph> {
        check_coefficients(order, &coeffs)?;
        let mut glyph = ShGlyph {
            basis,
            order,
            coeffs,
            normalization,
            raw_min: 0.0,
            raw_max: 0.0,
        };
        if normalization != RadiusNormalization::Raw {
            (glyph.raw_min, glyph.raw_max) = glyph.sample_extremes();
        }
        Ok(glyph)
    }

    pub fn basis(&self) -> ShBasis {
        self.basis
    }

    pub fn order(&self) -> u32 {
        self.order
    }

    pub fn coefficients(&self) -> &[f64] {
        &self.coeffs
    }

    pub fn normalization(&self) -> RadiusNormalization {
        self.normalization
    }

    /// Estimated `(min, max)` of the raw radius; `(0, 0)` for `Raw` glyphs (not computed).
    pub fn raw_range(&self) -> (f64, f64) {
        (self.raw_min, self.raw_max)
    }

    /// `Σ c_j Y_j(θ, φ)`. Non-finite angles give NaN.
    pub fn raw_radius(&self, theta: f64, phi: f64) -> f64 {
        evaluate_unchecked(self.basis, self.order, &self.coeffs, theta, phi)
    }

    /// The radius after normalisation.
    pub fn radius(&self, theta: f64, phi: f64) -> f64 {
        let r = self.raw_radius(theta, phi);
        match self.normalization {
            RadiusNormalization::Raw => r,
            RadiusNormalization::MinMax => {
                let span = self.raw_max - self.raw_min;
                if span <= 1e-12 * self.raw_max.abs().max(self.raw_min.abs()) {
                    1.0
                } else {
                    ((r - self.raw_min) / span).clamp(0.0, 1.0)
                }
            }
            RadiusNormalization::PositiveLobes => {
                if self.raw_max <= 0.0 {
                    0.0
                } else {
                    (r / self.raw_max).clamp(0.0, 1.0)
                }
            }
            RadiusNormalization::MaxAbs => {
                let m = self.raw_max.abs().max(self.raw_min.abs());
                if m == 0.0 {
                    0.0
                } else {
                    (r / m).clamp(-1.0, 1.0)
                }
            }
        }
    }

    /// The surface point `f(u, v) = radius(u, v) · d(u, v)` (`u` = θ, `v` = φ).
    pub fn position(&self, u: f32, v: f32) -> Vec3 {
        let (theta, phi) = (f64::from(u), f64::from(v));
        (unit_direction(theta, phi) * self.radius(theta, phi)).as_vec3()
    }

    fn sample_extremes(&self) -> (f64, f64) {
        extreme_directions(self.order)
            .into_iter()
            .map(|(theta, phi)| self.raw_radius(theta, phi))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r), hi.max(r))
            })
    }

    /// The same glyph under another radius mapping (the range estimate is kept; a `Raw` glyph,
    /// which has none, is sampled for it).
    pub fn renormalized(&self, normalization: RadiusNormalization) -> ShGlyph {
        let mut glyph = self.clone();
        glyph.normalization = normalization;
        if self.normalization == RadiusNormalization::Raw && normalization != self.normalization {
            (glyph.raw_min, glyph.raw_max) = glyph.sample_extremes();
        }
        glyph
    }

    /// [`ShGlyph::new`] with the raw radius range already known (e.g. from a basis table shared
    /// by many glyphs over [`extreme_directions`]), skipping the per-glyph sampling.
    pub fn with_raw_range(
        basis: ShBasis,
        order: u32,
        coeffs: Vec<f64>,
        normalization: RadiusNormalization,
        (raw_min, raw_max): (f64, f64),
    ) -> Result<ShGlyph> {
        check_coefficients(order, &coeffs)?;
        Ok(ShGlyph {
            basis,
            order,
            coeffs,
            normalization,
            raw_min,
            raw_max,
        })
    }
}

/// The directions (θ, φ) at which [`ShGlyph::new`] samples a glyph of `order` for its radius
/// range: a grid about π / (8 order) apart, one azimuth at each pole (where all are the same).
pub fn extreme_directions(order: u32) -> Vec<(f64, f64)> {
    let n_theta = 8 * order as usize + 17;
    let n_phi = 16 * order as usize + 32;
    let mut out = Vec::with_capacity(n_theta * n_phi);
    for i in 0..n_theta {
        let theta = PI * i as f64 / (n_theta - 1) as f64;
        let count = if i == 0 || i == n_theta - 1 { 1 } else { n_phi };
        for k in 0..count {
            out.push((theta, 2.0 * PI * k as f64 / n_phi as f64));
        }
    }
    out
}

/// `(sin θ cos φ, sin θ sin φ, cos θ)`.
pub fn unit_direction(theta: f64, phi: f64) -> DVec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    DVec3::new(st * cp, st * sp, ct)
}

/// Colour of a glyph point at offset `offset` from the glyph centre: `|normalize(offset)|`
/// per component (x → red, y → green, z → blue), so fibres along an axis share a hue whichever
/// way they point. A zero offset (a collapsed glyph) has no direction and is mid grey.
pub fn direction_colour(offset: Vec3) -> Vec3 {
    offset.try_normalize().map_or(Vec3::splat(0.5), Vec3::abs)
}

#[cfg(test)]
#[path = "glyph_tests.rs"]
mod tests;
