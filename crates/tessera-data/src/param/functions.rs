//! Parametric surfaces `f(u, v) -> R³` (paper E §3), evaluated in `f32` like the GPU shaders,
//! with the parameter ranges they are meant to be sampled over.
//!
//! Normals ([`surface_normal`]) come from finite differences, because paper E requires no
//! derivatives of its functions (§1) and several of them (the heart's branches, the seashell's
//! nodules) have no convenient analytic partials.

use std::f32::consts::{PI, TAU};

use glam::Vec3;

use super::glyph::ShGlyph;
use super::seashell::SeashellParams;
use super::yarn::YarnTube;
use crate::error::{DataError, Result};

/// The rectangle `[u0, u1] × [v0, v1]` a function is sampled over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamDomain {
    pub u: [f32; 2],
    pub v: [f32; 2],
}

impl ParamDomain {
    /// A domain with finite bounds and `u0 < u1`, `v0 < v1`.
    pub fn new(u: [f32; 2], v: [f32; 2]) -> Result<ParamDomain> {
        let ok = |r: [f32; 2]| r[0].is_finite() && r[1].is_finite() && r[0] < r[1];
        if !ok(u) || !ok(v) {
            return Err(DataError::Invalid(format!(
                "parameter domain needs finite, increasing ranges, got u = {u:?}, v = {v:?}"
            )));
        }
        Ok(ParamDomain { u, v })
    }

    pub fn area(&self) -> f64 {
        (f64::from(self.u[1]) - f64::from(self.u[0]))
            * (f64::from(self.v[1]) - f64::from(self.v[0]))
    }
}

/// A parametric object of one of the families paper E renders.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamFunction {
    /// Unit sphere, `u` = polar angle from +z in `[0, π]`, `v` = azimuth in `[0, 2π]`.
    Sphere,
    /// "Johi's Heart", paper E Listing 1 (`u ∈ [0, π]`, `v ∈ [0, 2π]`); see [`heart`].
    Heart,
    /// SH glyph, same parametrisation as [`ParamFunction::Sphere`].
    ShGlyph(ShGlyph),
    /// Seashell after Wilson's construction, `u` along the spiral, `v` around the opening.
    Seashell(SeashellParams),
    /// Tube around a plain-knit yarn or fibre curve, `u` along the curve, `v` around it.
    Yarn(YarnTube),
    /// A user's GLSL function over this domain, compiled into the GPU passes at run time; the
    /// CPU cannot evaluate it, so [`ParamFunction::position`] gives NaN.
    User(ParamDomain),
}

impl ParamFunction {
    pub fn domain(&self) -> ParamDomain {
        match self {
            ParamFunction::Sphere | ParamFunction::Heart | ParamFunction::ShGlyph(_) => {
                ParamDomain {
                    u: [0.0, PI],
                    v: [0.0, TAU],
                }
            }
            ParamFunction::Seashell(p) => p.domain(),
            ParamFunction::Yarn(t) => t.domain(),
            ParamFunction::User(d) => *d,
        }
    }

    /// `f(u, v)`. Any finite `(u, v)` evaluates (outside the domain the formula simply continues);
    /// NaN parameters give NaN positions.
    pub fn position(&self, u: f32, v: f32) -> Vec3 {
        match self {
            ParamFunction::Sphere => sphere(u, v),
            ParamFunction::Heart => heart(u, v),
            ParamFunction::ShGlyph(g) => g.position(u, v),
            ParamFunction::Seashell(p) => p.position(u, v),
            ParamFunction::Yarn(t) => t.position(u, v),
            ParamFunction::User(_) => Vec3::NAN,
        }
    }

    /// Unit normal at `(u, v)` oriented as `∂f/∂u × ∂f/∂v` ([`surface_normal`]); `None` where
    /// the surface is degenerate even after the pole treatment.
    pub fn normal(&self, u: f32, v: f32) -> Option<Vec3> {
        surface_normal(|u, v| self.position(u, v), &self.domain(), u, v)
    }
}

/// Unit sphere, z-up like the SH frame, so that an isotropic SH glyph is this sphere scaled:
/// `(sin u cos v, sin u sin v, cos u)`. `∂f/∂u × ∂f/∂v` points outwards.
pub fn sphere(u: f32, v: f32) -> Vec3 {
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    Vec3::new(su * cv, su * sv, cu)
}

/// "Johi's Heart" (paper E, Listing 1), y-up, in the listing's `f32` operation order (its
/// `#define PI 3.14159265359` rounds to `f32` `PI`).
///
/// The listing as printed starts from `vec3(sin(u) * cos(u), cos(u), sin(u) * cos(v))`, which
/// contradicts its own comment ("Start with a sphere shape"): it maps `v` and `2π - v` to the same
/// point, folding the surface onto itself. The authors' released shader (`johis_heart.glsl`,
/// cg-tuwien/FastRenderingOfParametricObjects) starts from the sphere
/// `(sin u cos v, cos u, sin u sin v)` instead; that is what is implemented. The remaining lines
/// follow the listing exactly. With this y-up sphere `∂f/∂u × ∂f/∂v` points inwards.
pub fn heart(u: f32, v: f32) -> Vec3 {
    let (su, cu) = u.sin_cos();
    let (sv, cv) = v.sin_cos();
    let mut p = Vec3::new(su * cv, cu, su * sv);
    if u < PI / 2.0 {
        p.y *= 1.0 - ((p.x * PI * 0.7).abs().sqrt().sqrt().cos() * 0.8);
    } else {
        p.x *= su * su;
    }
    p * Vec3::new(0.9, 1.0, 0.4)
}

/// Fraction of a parameter range used as the finite-difference step. These four constants reach
/// the shaders' port (`param/normal.glsl`) as defines.
pub const STEP_FRACTION: f32 = 1.0 / 1024.0;
/// How far into the domain a collapsed parameter line is re-measured, as a fraction of the range.
pub const NUDGE_FRACTION: f32 = 1.0 / 256.0;
/// Step along the re-measured line: wide, because the line is short and `f32` differences of
/// nearby points on it would be mostly rounding.
pub const NUDGE_STEP_FRACTION: f32 = 1.0 / 32.0;
/// A partial derivative this much shorter than the other one counts as collapsed.
pub const COLLAPSE_RATIO: f32 = 1e-3;

/// Unit normal `normalize(∂f/∂u × ∂f/∂v)` of `f` at `(u, v)`, robust at poles.
///
/// Partials are second-order finite differences with a step of 1/1024 of each parameter range:
/// central where the stencil stays inside `domain`, one-sided (`(-3f₀ + 4f₁ - f₂) / 2h`) at its
/// edges, so functions are never evaluated outside their range near a boundary.
///
/// At a pole a whole parameter line collapses to one point (e.g. the sphere at `u = 0`, where
/// `∂f/∂v = 0` for every `v`), and the cross product vanishes. When one partial is shorter than
/// 1/1000 of the other, it is replaced by the same partial measured on the line 1/256 of the
/// other parameter's range further inside the domain, with a step of 1/32 of its own range.
/// Near a pole `∂f/∂v(u, v) ≈ (u - u_pole) ∂²f/∂u∂v`, so the nearby line's tangent points along
/// `∂²f/∂u∂v`, which with `∂f/∂u` spans the limiting tangent plane; the sign of `u - u_pole`
/// on the inside gives the orientation that the neighbouring regular points have. On a sphere the result is exactly radial, because a central
/// difference along a circle is parallel to the circle's tangent at the midpoint.
///
/// Returns `None` when the surface is still degenerate (both partials vanish or are parallel),
/// or when `u`, `v` or `f` are not finite.
pub fn surface_normal(
    f: impl Fn(f32, f32) -> Vec3,
    domain: &ParamDomain,
    u: f32,
    v: f32,
) -> Option<Vec3> {
    if !u.is_finite() || !v.is_finite() {
        return None;
    }
    let (u_lo, u_hi) = (domain.u[0], domain.u[1]);
    let (v_lo, v_hi) = (domain.v[0], domain.v[1]);
    let (u_range, v_range) = (u_hi - u_lo, v_hi - v_lo);
    let hu = u_range * STEP_FRACTION;
    let hv = v_range * STEP_FRACTION;

    let mut du = derivative(|s| f(s, v), u, u_lo, u_hi, hu)?;
    let mut dv = derivative(|s| f(u, s), v, v_lo, v_hi, hv)?;

    if dv.length() < COLLAPSE_RATIO * du.length() {
        let u_in = nudge_inside(u, u_lo, u_hi, u_range * NUDGE_FRACTION);
        dv = derivative(|s| f(u_in, s), v, v_lo, v_hi, v_range * NUDGE_STEP_FRACTION)?;
    } else if du.length() < COLLAPSE_RATIO * dv.length() {
        let v_in = nudge_inside(v, v_lo, v_hi, v_range * NUDGE_FRACTION);
        du = derivative(|s| f(s, v_in), u, u_lo, u_hi, u_range * NUDGE_STEP_FRACTION)?;
    }
    let n = du.cross(dv);
    let scale = du.length() * dv.length();
    if !n.is_finite() || n.length() <= 1e-6 * scale || scale == 0.0 {
        return None;
    }
    Some(n.normalize())
}

/// Second-order finite difference of `g` at `x`, kept inside `[lo, hi]` when `x` is.
fn derivative(g: impl Fn(f32) -> Vec3, x: f32, lo: f32, hi: f32, h: f32) -> Option<Vec3> {
    let inside = x >= lo && x <= hi;
    let d = if !inside || (x - h >= lo && x + h <= hi) {
        (g(x + h) - g(x - h)) / (2.0 * h)
    } else if x + 2.0 * h <= hi {
        (g(x) * -3.0 + g(x + h) * 4.0 - g(x + 2.0 * h)) / (2.0 * h)
    } else if x - 2.0 * h >= lo {
        (g(x) * 3.0 - g(x - h) * 4.0 + g(x - 2.0 * h)) / (2.0 * h)
    } else {
        return None;
    };
    d.is_finite().then_some(d)
}

/// `x` moved by `by` towards the middle of `[lo, hi]`.
fn nudge_inside(x: f32, lo: f32, hi: f32, by: f32) -> f32 {
    if x - lo <= hi - x {
        x + by
    } else {
        x - by
    }
}

#[cfg(test)]
#[path = "functions_tests.rs"]
pub(crate) mod tests;
