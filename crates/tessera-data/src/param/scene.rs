//! Parametric scenes: objects (a [`ParamFunction`] placed by a transform) and the CPU bounds
//! every technique fits its view and culling to. The GPU encoding of a scene lives with the
//! techniques (`tessera::param::scene`).
//!
//! Adding a function: its family in [`super::functions`], its GPU encoding in tessera, and a
//! bound in [`ParamObject::object_radius`].

use glam::{Mat4, Vec3};

use super::reference::ReferenceObject;
use super::sh::sh_degrees_and_orders;
use super::{KnitCurve, ParamFunction, RadiusNormalization, SeashellParams, YarnTube};
use crate::camera::ViewUp;

/// Most objects one scene holds: the payload keeps at least 4 bits per parameter.
pub const MAX_OBJECTS: usize = 1 << 24;

/// Relative margin on the seashell's and the yarn's bounds for f32 evaluation: the bounds hold
/// for the exact surfaces, and f32 arithmetic strays from them by about 3e-7 of the size on
/// lavapipe; `tests/param_shapes.rs` accepts GPUs up to 1e-4 off, and this covers ten times that.
pub const EVALUATION_MARGIN: f64 = 1e-3;

/// One object: `object_to_world · f(u, v)`, coloured by `colour` (SH glyphs are coloured by
/// direction instead).
#[derive(Debug, Clone, PartialEq)]
pub struct ParamObject {
    pub function: ParamFunction,
    pub object_to_world: Mat4,
    pub colour: [f32; 3],
}

impl ParamObject {
    /// `function` at the origin, light grey.
    pub fn new(function: ParamFunction) -> ParamObject {
        ParamObject {
            function,
            object_to_world: Mat4::IDENTITY,
            colour: [0.85, 0.85, 0.85],
        }
    }

    pub fn with_transform(self, object_to_world: Mat4) -> ParamObject {
        ParamObject {
            object_to_world,
            ..self
        }
    }

    pub fn with_colour(self, colour: [f32; 3]) -> ParamObject {
        ParamObject { colour, ..self }
    }

    /// The object as `tessera_data::param::reference` takes it.
    pub fn reference(&self) -> ReferenceObject<'_> {
        ReferenceObject {
            function: &self.function,
            object_to_world: self.object_to_world,
            colour: Vec3::from(self.colour),
        }
    }

    /// A sphere around the origin of object space that holds the whole surface.
    pub fn object_radius(&self) -> f32 {
        match &self.function {
            // |f| <= 1 for both: the heart only shrinks the unit sphere's coordinates.
            ParamFunction::Sphere | ParamFunction::Heart => 1.0,
            ParamFunction::ShGlyph(g) => match g.normalization() {
                RadiusNormalization::MinMax
                | RadiusNormalization::MaxAbs
                | RadiusNormalization::PositiveLobes => 1.0,
                // |Y_l^m| <= sqrt(2 (2l + 1) / 4π) for every real basis here, so this bounds |r|.
                RadiusNormalization::Raw => sh_degrees_and_orders(g.order())
                    .map(|lm| {
                        lm.iter()
                            .zip(g.coefficients())
                            .map(|((l, _), c)| {
                                c.abs()
                                    * (2.0 * (2.0 * f64::from(*l) + 1.0)
                                        / (4.0 * std::f64::consts::PI))
                                        .sqrt()
                            })
                            .sum::<f64>() as f32
                    })
                    .unwrap_or(f32::INFINITY),
            },
            ParamFunction::Seashell(p) => seashell_radius(p),
            ParamFunction::Yarn(t) => yarn_radius(t),
            // Unknown until measured on the GPU (`UserFunction::measure_bounds` in tessera).
            ParamFunction::User(_) => f32::INFINITY,
        }
    }

    /// World-space bounding sphere (centre, radius).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let m = self.object_to_world;
        // The Frobenius norm of the linear part bounds how far it stretches any vector.
        let stretch = (m.x_axis.truncate().length_squared()
            + m.y_axis.truncate().length_squared()
            + m.z_axis.truncate().length_squared())
        .sqrt();
        (m.w_axis.truncate(), self.object_radius() * stretch)
    }
}

/// Bound on `|f(u, v)|` of a seashell over its domain. With `R = A·exp(θ cot α)`, the centre
/// `R·scale·(sin β sin θ, sin β cos θ, -cos β)` has length `R·scale`; the opening
/// `(0, b cos s, a sin s)` has length at most `max(|a|, |b|)` and keeps it under the rotations;
/// it is scaled by `R/A·scale·(1 + bump)` with `bump = (H_s/20)(H_θ/20)·G_s·G_θ` and
/// `0 ≤ G ≤ 1` (the exponent `-(W/N)^k f²` is never positive, as widths are not negative). So
/// `|f| ≤ R·scale·(1 + max(|a|, |b|)·(1 + |H_s H_θ|/400)/A)`, and `R` is largest at an end of
/// the domain `θ ∈ [0, 2π·turns]`.
pub fn seashell_radius(p: &SeashellParams) -> f32 {
    let f = f64::from;
    let end = f(p.domain().u[1]);
    let growth = 1.0 / f(p.alpha_deg).to_radians().tan();
    let radius = f(p.spiral_start) * (end * growth).exp().max(1.0);
    let opening = f(p.ellipse_a.abs().max(p.ellipse_b.abs()));
    let bump = (f(p.nodule_height_around) * f(p.nodule_height_along)).abs() / 400.0;
    let bound = radius * f(p.scale) * (1.0 + opening * (1.0 + bump) / f(p.spiral_start));
    (bound * (1.0 + EVALUATION_MARGIN)) as f32
}

/// Bound on `|f(u, v)|` of a yarn tube over its domain `t ∈ [0, T]`, `T = 2π·loops`: Crane's
/// curve `(t + a sin 2t, h cos t, d cos 2t)` has `x ∈ [-|a|, T + |a|]`, `|y| ≤ |h|`,
/// `|z| ≤ |d|`; a fibre lies `r` from it (along the orthonormal `N`, `B`), and the tube adds
/// its radius (unit spokes).
pub fn yarn_radius(t: &YarnTube) -> f32 {
    let k = t.knit();
    let reach = f64::from(t.domain().u[1]) + k.roundness.abs();
    let curve = (reach * reach + k.height * k.height + k.depth * k.depth).sqrt();
    let fibre = match t.curve() {
        KnitCurve::Yarn => 0.0,
        KnitCurve::Fiber { .. } => k.yarn_radius,
    };
    ((curve + fibre + t.tube_radius()) * (1.0 + EVALUATION_MARGIN)) as f32
}

/// The objects of one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ParamScene {
    pub objects: Vec<ParamObject>,
    /// The view up the data asks for (towards the head for a field read from a medical
    /// file that names an anatomical space); `None`: the viewer's default.
    pub up: Option<ViewUp>,
}

impl ParamScene {
    pub fn new(objects: Vec<ParamObject>) -> ParamScene {
        ParamScene { objects, up: None }
    }

    pub fn bounding_spheres(&self) -> Vec<(Vec3, f32)> {
        self.objects
            .iter()
            .map(ParamObject::bounding_sphere)
            .collect()
    }

    /// Every SH glyph under `normalization` ([`ShGlyph::renormalized`]); other objects as
    /// they are.
    pub fn with_glyph_radius(mut self, normalization: RadiusNormalization) -> ParamScene {
        for o in &mut self.objects {
            if let ParamFunction::ShGlyph(g) = &o.function {
                o.function = ParamFunction::ShGlyph(g.renormalized(normalization));
            }
        }
        self
    }

    pub fn reference_objects(&self) -> Vec<ReferenceObject<'_>> {
        self.objects.iter().map(ParamObject::reference).collect()
    }
}

#[cfg(test)]
#[path = "scene_tests.rs"]
mod tests;
