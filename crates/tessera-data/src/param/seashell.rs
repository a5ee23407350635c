//! Parametric seashell after B. Wilson, "Building a Parametric Seashell" (Observable, 2022),
//! which paper E §5 cites as `[Wil22]` and "follows roughly". Wilson's construction is the
//! classic Cortie/Picado model: an elliptical opening swept along a logarithmic helico-spiral,
//! growing with it, plus Gaussian nodules in both directions.
//!
//! Paper E gives no numbers; the defaults are those of the authors' released shader
//! (`seashells.glsl`, variant 1 of cg-tuwien/FastRenderingOfParametricObjects), whose
//! parametrisation is implemented here:
//!
//! * `u = θ ∈ [0, 2π·turns]` runs along the spiral, `v = s ∈ [0, 2π]` around the opening.
//! * Spiral radius `R(θ) = A·exp(θ·cot α)`; the opening's centre is
//!   `scale·R·(sin β sin θ, sin β cos θ, -cos β)`.
//! * The opening `(0, b cos s, a sin s)` is tilted by `Rz(-ω)·Ry(-μ)·Rx(-φ)`, turned with the
//!   spiral by `Rz(-θ)`, and scaled by `scale·R/A·(1 + bump)`.
//! * `bump = (H_s/20)(H_θ/20)·G_s·G_θ`, with `G = exp(-(W/N)^k · f²)`, where
//!   `f = t - round(t)`, `t = (angle - offset)/(2π/N)` is the signed fraction of the way to the
//!   nearest of the `N` nodules per turn (in `s` around the opening, in `θ` along the spiral).
//! * The result is turned y-up by swapping y and z.

use std::f32::consts::TAU;

use glam::{Mat3, Vec3};

use super::functions::ParamDomain;
use crate::error::{DataError, Result};

/// All parameters of the seashell model (angles in degrees, as in Wilson's notebook).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeashellParams {
    /// Spiral turns swept by `u`.
    pub turns: f32,
    /// `A`: distance of the opening from the axis at `θ = 0` (model units before `scale`).
    pub spiral_start: f32,
    /// `α`: angle between the spiral's tangent and its radius; growth per radian is `cot α`.
    pub alpha_deg: f32,
    /// `β`: enlarging angle, how fast the spiral advances along the shell axis.
    pub beta_deg: f32,
    /// Half-axes of the elliptical opening: `a` across the opening, `b` along the axis.
    pub ellipse_a: f32,
    pub ellipse_b: f32,
    /// Tilt of the opening about the front-to-back (`φ`), top-to-bottom (`ω`) and side-to-side
    /// (`μ`) axes.
    pub phi_deg: f32,
    pub omega_deg: f32,
    pub mu_deg: f32,
    /// Nodules around the opening: height (20 = unit factor), count, width, offset, spikiness.
    pub nodule_height_around: f32,
    pub nodules_around: f32,
    pub nodule_width_around: f32,
    pub nodule_offset_around_deg: f32,
    pub nodule_spikiness_around: f32,
    /// Nodules along the spiral, per turn.
    pub nodule_height_along: f32,
    pub nodules_along: f32,
    pub nodule_width_along: f32,
    pub nodule_offset_along_deg: f32,
    pub nodule_spikiness_along: f32,
    /// Overall scale from model units to world units.
    pub scale: f32,
}

impl Default for SeashellParams {
    /// Variant 1 of the authors' code: large rounded nodules.
    fn default() -> SeashellParams {
        SeashellParams {
            turns: 8.0,
            spiral_start: 25.0,
            alpha_deg: 87.0,
            beta_deg: 29.0,
            ellipse_a: 4.309,
            ellipse_b: 4.7,
            phi_deg: 60.674,
            omega_deg: 7.584,
            mu_deg: -39.944,
            nodule_height_around: 20.0,
            nodules_around: 9.0,
            nodule_width_around: 58.839,
            nodule_offset_around_deg: 52.331,
            nodule_spikiness_around: 1.5,
            nodule_height_along: 5.674,
            nodules_along: 20.0,
            nodule_width_along: 125.4,
            nodule_offset_along_deg: 40.65,
            nodule_spikiness_along: 2.0,
            scale: 0.01,
        }
    }
}

impl SeashellParams {
    /// Variant 2 of the authors' code: a slender shell with ridges along the spiral only.
    pub fn ridged() -> SeashellParams {
        SeashellParams {
            alpha_deg: 86.5,
            beta_deg: 10.0,
            ellipse_a: 6.071,
            ellipse_b: 5.153,
            nodule_width_around: 1.0,
            nodules_along: 11.0,
            nodule_spikiness_along: 1.5,
            ..SeashellParams::default()
        }
    }

    /// Variant 3 of the authors' code (paper E Fig. 3f): many tiny bumps, i.e. sub-pixel detail.
    pub fn fine_bumps() -> SeashellParams {
        SeashellParams {
            nodule_width_around: 100.0,
            nodules_around: 50.0,
            nodules_along: 70.0,
            nodule_height_around: 10.0,
            nodule_height_along: 2.837,
            nodule_spikiness_around: 4.0,
            nodule_spikiness_along: 5.0,
            ..SeashellParams::ridged()
        }
    }

    /// Checks that every parameter is finite and the ones used as divisors or growth rates are
    /// in range, so that [`SeashellParams::position`] is finite over the whole domain.
    pub fn validate(&self) -> Result<()> {
        let all = [
            self.turns,
            self.spiral_start,
            self.alpha_deg,
            self.beta_deg,
            self.ellipse_a,
            self.ellipse_b,
            self.phi_deg,
            self.omega_deg,
            self.mu_deg,
            self.nodule_height_around,
            self.nodules_around,
            self.nodule_width_around,
            self.nodule_offset_around_deg,
            self.nodule_spikiness_around,
            self.nodule_height_along,
            self.nodules_along,
            self.nodule_width_along,
            self.nodule_offset_along_deg,
            self.nodule_spikiness_along,
            self.scale,
        ];
        let problem = if all.iter().any(|x| !x.is_finite()) {
            Some("all parameters must be finite")
        } else if self.turns <= 0.0 || self.spiral_start <= 0.0 || self.scale <= 0.0 {
            Some("turns, spiral_start and scale must be positive")
        } else if self.alpha_deg <= 0.0 || self.alpha_deg >= 180.0 {
            Some("alpha_deg must lie strictly between 0 and 180")
        } else if self.nodules_around <= 0.0 || self.nodules_along <= 0.0 {
            Some("nodule counts must be positive")
        } else if self.nodule_width_around < 0.0 || self.nodule_width_along < 0.0 {
            Some("nodule widths must not be negative")
        } else {
            None
        };
        match problem {
            Some(p) => Err(DataError::Invalid(format!("seashell: {p}"))),
            None => Ok(()),
        }
    }

    /// `u ∈ [0, 2π·turns]`, `v ∈ [0, 2π]`.
    pub fn domain(&self) -> ParamDomain {
        ParamDomain {
            u: [0.0, TAU * self.turns],
            v: [0.0, TAU],
        }
    }

    /// The surface point at spiral angle `u` and opening angle `v` (see the module doc).
    pub fn position(&self, u: f32, v: f32) -> Vec3 {
        let (theta, s) = (u, v);
        let growth = self.alpha_deg.to_radians().tan().recip();
        let radius = self.spiral_start * (theta * growth).exp();
        let beta = self.beta_deg.to_radians();
        let (sin_t, cos_t) = theta.sin_cos();
        let centre =
            Vec3::new(beta.sin() * sin_t, beta.sin() * cos_t, -beta.cos()) * (radius * self.scale);

        let (sin_s, cos_s) = s.sin_cos();
        let opening = Vec3::new(0.0, self.ellipse_b * cos_s, self.ellipse_a * sin_s);
        let tilt = Mat3::from_rotation_z(-self.omega_deg.to_radians())
            * Mat3::from_rotation_y(-self.mu_deg.to_radians())
            * Mat3::from_rotation_x(-self.phi_deg.to_radians());
        let turned = Mat3::from_rotation_z(-theta) * (tilt * opening);

        let around = nodule(
            s,
            self.nodules_around,
            self.nodule_offset_around_deg,
            self.nodule_width_around,
            self.nodule_spikiness_around,
        );
        let along = nodule(
            theta,
            self.nodules_along,
            self.nodule_offset_along_deg,
            self.nodule_width_along,
            self.nodule_spikiness_along,
        );
        let bump =
            (self.nodule_height_around / 20.0) * (self.nodule_height_along / 20.0) * around * along;

        let p = centre + turned * (radius / self.spiral_start * self.scale * (1.0 + bump));
        Vec3::new(p.x, p.z, p.y)
    }
}

/// Gaussian nodule profile `exp(-(W/N)^k · f²)`, `f` the signed fraction of a period to the
/// nearest of `count` nodules per turn (so the profile is periodic and peaks at the nodules).
fn nodule(angle: f32, count: f32, offset_deg: f32, width: f32, spikiness: f32) -> f32 {
    let t = (angle - offset_deg.to_radians()) / (TAU / count);
    let f = t - t.round();
    (-(width / count).powf(spikiness) * f * f).exp()
}

#[cfg(test)]
#[path = "seashell_tests.rs"]
mod tests;
