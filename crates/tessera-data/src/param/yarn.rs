//! Plain-knit yarn after K. Crane, "A Simple Parametric Model of Plain-Knit Yarns" (2023,
//! github.com/keenancrane/plain-knit-yarn), cited by paper E as `[Cra23]`, extruded into tubes as
//! paper E §5 describes.
//!
//! Crane's yarn curve for one row is `γ(t) = (t + a sin 2t, h cos t, d cos 2t)`, one loop per
//! `2π` of `t`, with loop roundness `a`, height `h` and depth `d`. Its fibres wind around it:
//! `η(t) = γ(t) + r (cos θ(t) N(t) + sin θ(t) B(t))`, `θ(t) = ωt - 2 cos t + φ`, where `N`, `B`
//! are the Frenet normal and binormal of `γ`, `r` the yarn radius, `ω` the twist and `φ` the
//! fibre's phase (`2πi/n` for fibre `i` of `n`). Defaults are Crane's: `a = 3/2`, `h = 4`,
//! `d = 1`, `r = 1/2`, `ω = 5`, rows `h + 1/2` apart.
//!
//! The tube (paper E §5): `u` runs along the curve; at each point a unit vector orthogonal to the
//! tangent is rotated about the tangent by `v ∈ [0, 2π)` (Rodrigues' formula) and scaled by the
//! tube radius. The orthogonal vector is `normalize(t.y, -t.x, 0)` as in the authors' code; it is
//! smooth wherever the tangent is not parallel to z, which holds for Crane's curves since
//! `γ'.x = 1 + 2a cos 2t` and `γ'.y = -h sin t` cannot vanish together unless `a = -1/2`.
//! Everything is computed in `f64` and rounded to `f32` at the end, so the tube radius is exact
//! to `f32` precision. Tangents are analytic (fibres: [`KnitParams::fiber_velocity`]), so the
//! GPU (`tessera::param`, `functions.glsl`) can evaluate the same formulas in `f32`.

use std::f64::consts::TAU;

use glam::{DVec3, Vec3};

use super::functions::ParamDomain;
use crate::error::{DataError, Result};

/// Crane's knit parameters for one row of loops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnitParams {
    /// `a`: loop roundness.
    pub roundness: f64,
    /// `h`: loop height.
    pub height: f64,
    /// `d`: loop depth.
    pub depth: f64,
    /// `r`: distance of the fibres from the yarn centreline.
    pub yarn_radius: f64,
    /// `ω`: fibre twist.
    pub twist: f64,
    /// Loops in the row; `u` spans `[0, 2π·loops]`.
    pub loops: u32,
}

impl Default for KnitParams {
    fn default() -> KnitParams {
        KnitParams {
            roundness: 1.5,
            height: 4.0,
            depth: 1.0,
            yarn_radius: 0.5,
            twist: 5.0,
            loops: 4,
        }
    }
}

impl KnitParams {
    /// Crane's spacing of consecutive rows (`h + 1/2`), for laying out fabric.
    pub fn row_offset(&self) -> f64 {
        self.height + 0.5
    }

    /// Yarn centreline `γ(t)`.
    pub fn yarn_curve(&self, t: f64) -> DVec3 {
        let (a, h, d) = (self.roundness, self.height, self.depth);
        DVec3::new(t + a * (2.0 * t).sin(), h * t.cos(), d * (2.0 * t).cos())
    }

    /// `γ'(t)`.
    pub fn yarn_velocity(&self, t: f64) -> DVec3 {
        let (a, h, d) = (self.roundness, self.height, self.depth);
        DVec3::new(
            1.0 + 2.0 * a * (2.0 * t).cos(),
            -h * t.sin(),
            -2.0 * d * (2.0 * t).sin(),
        )
    }

    /// `γ''(t)`.
    pub fn yarn_acceleration(&self, t: f64) -> DVec3 {
        let (a, h, d) = (self.roundness, self.height, self.depth);
        DVec3::new(
            -4.0 * a * (2.0 * t).sin(),
            -h * t.cos(),
            -4.0 * d * (2.0 * t).cos(),
        )
    }

    /// `γ'''(t)`.
    pub fn yarn_jerk(&self, t: f64) -> DVec3 {
        let (a, h, d) = (self.roundness, self.height, self.depth);
        DVec3::new(
            -8.0 * a * (2.0 * t).cos(),
            h * t.sin(),
            8.0 * d * (2.0 * t).sin(),
        )
    }

    /// Frenet frame `(T, N, B)` of the yarn curve. `N` is the normalised derivative of the unit
    /// tangent, `T'·|γ'| = γ'' - γ'(γ'·γ'')/|γ'|²`; where the curvature vanishes `N` is undefined,
    /// and the tube's orthogonal vector is used instead so that fibres stay finite.
    pub fn frenet_frame(&self, t: f64) -> [DVec3; 3] {
        let v = self.yarn_velocity(t);
        let acc = self.yarn_acceleration(t);
        let tangent = v.try_normalize().unwrap_or(DVec3::X);
        let bend = acc - v * (v.dot(acc) / v.length_squared());
        let normal = bend.try_normalize().unwrap_or_else(|| orthogonal(tangent));
        [tangent, normal, tangent.cross(normal)]
    }

    /// Fibre curve `η(t)` with phase `phase` (Crane's `φ`).
    pub fn fiber_curve(&self, t: f64, phase: f64) -> DVec3 {
        let [_, n, b] = self.frenet_frame(t);
        let angle = t * self.twist - 2.0 * t.cos() + phase;
        self.yarn_curve(t) + (n * angle.cos() + b * angle.sin()) * self.yarn_radius
    }

    /// `η'(t)`, analytically, so that the GPU can evaluate the same formula in `f32` (a
    /// difference quotient needs `f64` to be accurate). With speed `s = |γ'|`, curvature `κ` and
    /// torsion `τ`, Frenet–Serret gives `N' = s(τB - κT)` and `B' = -sτN`, hence
    /// `η' = s(1 - rκ cos θ) T + r(θ' + sτ)(cos θ B - sin θ N)` with `θ' = ω + 2 sin t`,
    /// `sκ = |γ'×γ''|/s²` and `sτ = s (γ'×γ'')·γ'''/|γ'×γ''|²`. Where the curvature vanishes
    /// (the frame's fallback) `κ = τ = 0`, which keeps `η'` finite.
    pub fn fiber_velocity(&self, t: f64, phase: f64) -> DVec3 {
        let [tangent, normal, binormal] = self.frenet_frame(t);
        let v = self.yarn_velocity(t);
        let bend = v.cross(self.yarn_acceleration(t));
        let bend2 = bend.length_squared();
        let speed = v.length();
        let (curving, twisting) = if bend2 > 0.0 && bend2.is_finite() {
            (
                bend2.sqrt() / v.length_squared(),
                speed * bend.dot(self.yarn_jerk(t)) / bend2,
            )
        } else {
            (0.0, 0.0)
        };
        let angle = t * self.twist - 2.0 * t.cos() + phase;
        let (sin_a, cos_a) = angle.sin_cos();
        let turn = self.twist + 2.0 * t.sin();
        let r = self.yarn_radius;
        tangent * (speed - r * curving * cos_a)
            + (binormal * cos_a - normal * sin_a) * (r * (turn + twisting))
    }

    fn validate(&self) -> Result<()> {
        let finite = [
            self.roundness,
            self.height,
            self.depth,
            self.yarn_radius,
            self.twist,
        ]
        .iter()
        .all(|x| x.is_finite());
        if !finite || self.loops == 0 || self.yarn_radius < 0.0 {
            return Err(DataError::Invalid(format!(
                "knit parameters must be finite with at least one loop and a non-negative yarn radius, got {self:?}"
            )));
        }
        Ok(())
    }
}

/// Which of Crane's curves a tube follows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum KnitCurve {
    /// The yarn centreline `γ`.
    Yarn,
    /// A fibre `η` with the given phase.
    Fiber { phase: f64 },
}

/// A tube of radius `tube_radius` around a yarn or fibre curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YarnTube {
    knit: KnitParams,
    curve: KnitCurve,
    tube_radius: f64,
}

impl YarnTube {
    pub fn new(knit: KnitParams, curve: KnitCurve, tube_radius: f64) -> Result<YarnTube> {
        knit.validate()?;
        let phase_ok = match curve {
            KnitCurve::Yarn => true,
            KnitCurve::Fiber { phase } => phase.is_finite(),
        };
        if !phase_ok || !tube_radius.is_finite() || tube_radius <= 0.0 {
            return Err(DataError::Invalid(format!(
                "yarn tube needs a finite fibre phase and a positive tube radius, got {curve:?}, radius {tube_radius}"
            )));
        }
        Ok(YarnTube {
            knit,
            curve,
            tube_radius,
        })
    }

    /// The `count` fibres of one yarn, phases `2πi/count` as in Crane's code.
    pub fn fibers(knit: KnitParams, count: u32, tube_radius: f64) -> Result<Vec<YarnTube>> {
        if count == 0 {
            return Err(DataError::Invalid("a yarn needs at least one fibre".into()));
        }
        (0..count)
            .map(|i| {
                let phase = TAU * f64::from(i) / f64::from(count);
                YarnTube::new(knit, KnitCurve::Fiber { phase }, tube_radius)
            })
            .collect()
    }

    pub fn knit(&self) -> &KnitParams {
        &self.knit
    }

    pub fn curve(&self) -> KnitCurve {
        self.curve
    }

    pub fn tube_radius(&self) -> f64 {
        self.tube_radius
    }

    /// `u ∈ [0, 2π·loops]`, `v ∈ [0, 2π]`.
    pub fn domain(&self) -> ParamDomain {
        ParamDomain {
            u: [0.0, (TAU * f64::from(self.knit.loops)) as f32],
            v: [0.0, TAU as f32],
        }
    }

    /// The curve the tube follows, at curve parameter `t`.
    pub fn centre(&self, t: f64) -> DVec3 {
        match self.curve {
            KnitCurve::Yarn => self.knit.yarn_curve(t),
            KnitCurve::Fiber { phase } => self.knit.fiber_curve(t, phase),
        }
    }

    /// Unit tangent of the followed curve, from its analytic velocity.
    pub fn tangent(&self, t: f64) -> DVec3 {
        let d = match self.curve {
            KnitCurve::Yarn => self.knit.yarn_velocity(t),
            KnitCurve::Fiber { phase } => self.knit.fiber_velocity(t, phase),
        };
        d.try_normalize().unwrap_or(DVec3::X)
    }

    /// The tube point at curve parameter `u`, angle `v` around the curve.
    pub fn position(&self, u: f32, v: f32) -> Vec3 {
        let t = f64::from(u);
        let tangent = self.tangent(t);
        let side = orthogonal(tangent);
        let spoke = rotate_about(side, tangent, f64::from(v));
        (self.centre(t) + spoke * self.tube_radius).as_vec3()
    }
}

/// Unit vector orthogonal to unit `t`: `normalize(t.y, -t.x, 0)`, or x (made orthogonal) when
/// `t` is parallel to z.
fn orthogonal(t: DVec3) -> DVec3 {
    let flat = DVec3::new(t.y, -t.x, 0.0);
    let seed = if flat.length_squared() > 1e-18 {
        flat
    } else {
        DVec3::X
    };
    (seed - t * seed.dot(t)).normalize()
}

/// Rodrigues' rotation of `x` about unit `axis` by `angle`.
fn rotate_about(x: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    x * c + axis.cross(x) * s + axis * (axis.dot(x) * (1.0 - c))
}

#[cfg(test)]
#[path = "yarn_tests.rs"]
mod tests;
