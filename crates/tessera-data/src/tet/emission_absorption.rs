//! Front-to-back emission–absorption through a tet mesh, the exact ray–tet integrator of
//! [`super::optical`] and [`super::scalar_integral`] extended from sums to compositing: the
//! ground truth for shell traversal (paper B) and its shadow rays.
//!
//! Per tet stretch the scalar runs linearly, so the optical depth `τ = length × mean of the
//! absorption table over the scalar's run` is exact, as is the emitted amount
//! `E = length × mean of the emission table`. Inside a stretch, emission is attenuated as if
//! both coefficients were their means: `colour += T · E · (1 − e^(−τ)) / τ`, `T ·= e^(−τ)`
//! (Max's closed form for a homogeneous stretch). Pure absorption is therefore exact; with
//! emission the error shrinks with the square of the stretch's change in absorption.

use glam::DVec3;

use super::optical::{interval, world_tet, MeshFrame, RayStretch};
use super::scalar_integral::{tet_linears, TetLinear};
use super::TetMesh;
use crate::transfer::{IntegrandTable, ScalarMode, TransferFunction, TABLE_KNOTS};

/// Opacity at which a radiance ray stops (paper B, §5.2: 98 %).
pub const EARLY_TERMINATION_OPACITY: f64 = 0.98;

/// The optical model: absorption and emission per unit length as functions of the
/// normalized scalar, tables as interval shading builds them.
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionAbsorption {
    pub absorption: IntegrandTable,
    pub emission: IntegrandTable,
}

impl EmissionAbsorption {
    /// The largest absorption coefficient of any channel at any scalar: what "dense" is
    /// measured against (gradient shading's threshold).
    pub fn max_absorption(&self) -> f64 {
        self.absorption
            .values
            .iter()
            .flatten()
            .fold(0.0, |m, &v| m.max(f64::from(v)))
    }

    /// The tables of `tf` at `density` (world units: the mesh's longest side is 1).
    pub fn new(tf: &TransferFunction, density: f32) -> EmissionAbsorption {
        EmissionAbsorption {
            absorption: IntegrandTable::new(tf, ScalarMode::Absorption, density, TABLE_KNOTS),
            emission: IntegrandTable::new(tf, ScalarMode::Emission, density, TABLE_KNOTS),
        }
    }
}

/// Colour gathered and light let through so far along a ray, front to back, per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontToBack {
    pub colour: DVec3,
    pub transmittance: DVec3,
}

impl Default for FrontToBack {
    fn default() -> Self {
        FrontToBack {
            colour: DVec3::ZERO,
            transmittance: DVec3::ONE,
        }
    }
}

impl FrontToBack {
    /// Adds a stretch of `length` along which the scalar runs from `s_in` to `s_out`. A
    /// stretch without length adds nothing, whatever its scalars: a flat tet's are not finite.
    pub fn add_stretch(&mut self, optics: &EmissionAbsorption, s_in: f64, s_out: f64, length: f64) {
        self.add_lit_stretch(optics, s_in, s_out, length, DVec3::ONE);
    }

    /// [`FrontToBack::add_stretch`] with the stretch's emission scaled by `light` per channel
    /// (shadows, ambient occlusion, shading); absorption is untouched. A factor of one adds
    /// exactly what `add_stretch` adds.
    pub fn add_lit_stretch(
        &mut self,
        optics: &EmissionAbsorption,
        s_in: f64,
        s_out: f64,
        length: f64,
        light: DVec3,
    ) {
        if !(length > 0.0 && s_in.is_finite() && s_out.is_finite()) {
            return;
        }
        let tau = optics.absorption.average(s_in, s_out) * length;
        let emitted = optics.emission.average(s_in, s_out) * length * light;
        let attenuated = DVec3::from_array(std::array::from_fn(|c| {
            let t = tau[c];
            // (1 - e^-τ)/τ without cancellation for thin stretches.
            if t > 1e-6 {
                -(-t).exp_m1() / t
            } else {
                1.0 - 0.5 * t
            }
        }));
        self.colour += self.transmittance * emitted * attenuated;
        self.transmittance *= DVec3::from_array(tau.to_array().map(|t| (-t).exp()));
    }

    /// Opacity as early termination reads it: that of the most transparent channel, so a
    /// ray stops only once every channel is opaque enough.
    pub fn opacity(&self) -> f64 {
        1.0 - self.transmittance.max_element()
    }

    pub fn is_opaque(&self) -> bool {
        self.opacity() >= EARLY_TERMINATION_OPACITY
    }

    /// The colour over `background`.
    pub fn over(&self, background: DVec3) -> DVec3 {
        self.colour + self.transmittance * background
    }
}

/// A stretch of a ray inside one tet: `(tet, t_enter, t_exit)`.
pub type TetStretch = (usize, f64, f64);

/// Every tet of a mesh in world space (placed by [`MeshFrame::of`]) with its linear scalar,
/// intersected one by one: the exact, slow reference.
pub struct ExactRayIntegrator {
    corners: Vec<[DVec3; 4]>,
    linears: Vec<TetLinear>,
}

impl ExactRayIntegrator {
    /// `normalized` holds one scalar in [0, 1] per vertex
    /// ([`super::scalar_integral::normalized_scalars`]). Panics on vertex indices out of range
    /// (run [`TetMesh::validate`] first).
    pub fn new(mesh: &TetMesh, normalized: &[f32]) -> ExactRayIntegrator {
        let frame = MeshFrame::of(mesh);
        ExactRayIntegrator {
            corners: (0..mesh.tets.len())
                .map(|t| world_tet(mesh, &frame, t))
                .collect(),
            linears: tet_linears(mesh, normalized),
        }
    }

    /// The stretches of `origin + t * dir` (`dir` of unit length) inside tets, clipped to
    /// `[t_min, t_max]`, sorted by entry.
    pub fn crossed(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> Vec<TetStretch> {
        let mut stretches: Vec<TetStretch> = self
            .corners
            .iter()
            .enumerate()
            .filter_map(|(t, c)| {
                let (enter, exit) = interval(origin, dir, c)?;
                let (enter, exit) = (enter.max(t_min), exit.min(t_max));
                (exit > enter).then_some((t, enter, exit))
            })
            .collect();
        stretches.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)));
        stretches
    }

    /// Adds the stretch of tet `tet` from `enter` to `exit` along `origin + t * dir`.
    pub fn add(
        &self,
        sum: &mut FrontToBack,
        optics: &EmissionAbsorption,
        (tet, enter, exit): TetStretch,
        origin: DVec3,
        dir: DVec3,
    ) {
        let stretch = RayStretch {
            eye: origin,
            dir,
            enter,
            exit,
        };
        let (s_in, s_out) = self.linears[tet].at_ends(&stretch);
        sum.add_stretch(optics, s_in, s_out, exit - enter);
    }

    /// Emission–absorption along the ray front to back, stopping early at
    /// [`EARLY_TERMINATION_OPACITY`] when `early_termination` is set.
    pub fn integrate(
        &self,
        optics: &EmissionAbsorption,
        origin: DVec3,
        dir: DVec3,
        (t_min, t_max): (f64, f64),
        early_termination: bool,
    ) -> FrontToBack {
        let mut sum = FrontToBack::default();
        for stretch in self.crossed(origin, dir, t_min, t_max) {
            if early_termination && sum.is_opaque() {
                break;
            }
            self.add(&mut sum, optics, stretch, origin, dir);
        }
        sum
    }
}

#[cfg(test)]
#[path = "emission_absorption_tests.rs"]
mod tests;
