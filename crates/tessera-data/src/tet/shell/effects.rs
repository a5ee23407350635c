//! The secondary-ray effects of shell traversal (paper B, §6) as one shading model that the
//! CPU reference and the GPU share: volumetric shadows from a point or directional light with
//! a ground plane below the mesh, ambient occlusion by hemisphere rays, and gradient shading
//! with each tet's exact scalar gradient as the normal. The GPU receives the constants here as
//! `#define`s.
//!
//! # Where secondary rays start
//! Every tet stretch of a primary ray is shaded with the lighting of its tet, and the secondary
//! rays are cast once per tet, from its centroid ([`super::lighting`]), not once per stretch
//! and pixel. A tet is crossed by many pixel rays, so far fewer rays are cast and their number
//! follows the mesh, not the image or the view; each effect becomes a pass of its own that a
//! GPU timer measures; and the GPU's per-tet results compare one to one with the CPU's. The
//! price is lighting that is constant inside a tet: a shadow's edge is as sharp as the mesh is
//! fine. What depends on the view (the light and view directions of the diffuse and specular
//! terms) is evaluated per stretch, at its midpoint.
//!
//! # The model
//! A stretch with mean emission `E` emits
//! `E · ao · (AMBIENT + (1 − AMBIENT) · L · mix(1, diffuse, w) + L · w · specular)`:
//! `ao` the tet's mean transmittance over its AO rays (1 without AO), `L` its transmittance
//! towards the light (1 without shadows), `w` the gradient-shading weight (0 without gradient
//! shading; see [`gradient_weight`]). With every effect off nothing is scaled.

use glam::{DVec3, Vec3};

use super::render::Light;
use crate::error::{DataError, Result};
use crate::shading;

/// Share of a stretch's emission that needs no light: shadowed regions stay readable.
pub const VOLUME_AMBIENT: f32 = 0.3;
/// Mean absorption, relative to the transfer function's largest, from which gradient shading
/// applies in full (the paper shades "high-density regions" only).
pub const GRADIENT_THRESHOLD: f32 = 0.25;
/// Width of the ramp below [`GRADIENT_THRESHOLD`] over which gradient shading fades in: a
/// ramp, not a step, so that `f32` and `f64` landing on either side make no visible jump.
pub const GRADIENT_RAMP: f32 = 0.1;
/// Albedo of the ground plane.
pub const GROUND_ALBEDO: [f32; 3] = [0.8, 0.8, 0.78];
/// Distance of the ground plane below the mesh's lowest point (world units).
pub const GROUND_GAP: f32 = 0.02;
/// Half the side of the square ground plane, centred under the mesh (world units; the mesh's
/// longest side is 1).
pub const GROUND_HALF_EXTENT: f32 = 1.0;
/// Most AO rays per tet (the GPU keeps the pattern in a constant array).
pub const MAX_AO_SAMPLES: u32 = 64;
/// AO radius when none is given (world units).
pub const DEFAULT_AO_RADIUS: f32 = 0.1;
/// The hemisphere's axis where a tet's gradient vanishes.
pub const AO_FALLBACK_NORMAL: [f32; 3] = [0.0, 1.0, 0.0];

/// Ambient occlusion: `samples` rays over the hemisphere, each `radius` long.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AmbientOcclusion {
    pub samples: u32,
    pub radius: f32,
}

impl AmbientOcclusion {
    /// Checked settings: 1 to [`MAX_AO_SAMPLES`] rays of a positive, finite radius.
    pub fn new(samples: u32, radius: f32) -> Result<AmbientOcclusion> {
        if !(1..=MAX_AO_SAMPLES).contains(&samples) {
            return Err(DataError::Invalid(format!(
                "ambient occlusion takes 1 to {MAX_AO_SAMPLES} rays, not {samples}"
            )));
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(DataError::Invalid(format!(
                "the ambient occlusion radius must be a positive number, not {radius}"
            )));
        }
        Ok(AmbientOcclusion { samples, radius })
    }
}

/// Which effects shade a shell traversal image; the default has none.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShellEffects {
    /// Volumetric shadows cast by this light, and the ground plane they fall on.
    pub shadows: Option<Light>,
    pub ambient_occlusion: Option<AmbientOcclusion>,
    /// Diffuse and specular terms with each tet's scalar gradient as the normal.
    pub gradient: bool,
}

impl ShellEffects {
    pub fn any(&self) -> bool {
        self.shadows.is_some() || self.ambient_occlusion.is_some() || self.gradient
    }

    /// Whether per-tet gradients are needed: for shading, and to orient AO hemispheres.
    pub fn needs_gradients(&self) -> bool {
        self.gradient || self.ambient_occlusion.is_some()
    }

    /// The light that shades: the shadows' light, else `headlight` (a direction).
    pub fn light(&self, headlight: DVec3) -> Light {
        self.shadows.unwrap_or(Light::Directional(headlight))
    }
}

/// Counts of the secondary rays one image cast.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SecondaryStats {
    /// Towards the light: one per tet and one per pixel that sees the ground plane.
    pub shadow_rays: u64,
    pub ao_rays: u64,
    /// Tets the secondary rays marched through.
    pub steps: u64,
    /// Segments of secondary rays that the traversal's loop guard ended.
    pub guard_hits: u64,
}

impl SecondaryStats {
    pub fn add(&mut self, other: &SecondaryStats) {
        self.shadow_rays += other.shadow_rays;
        self.ao_rays += other.ao_rays;
        self.steps += other.steps;
        self.guard_hits += other.guard_hits;
    }
}

impl Light {
    /// A directional light from above (`up`), tilted to the side so that shadows fall beside
    /// the mesh on the ground plane: what `--shadows` alone lights with.
    pub fn above(up: DVec3) -> Light {
        let up = up.normalize_or(DVec3::Y);
        let (a, b) = hemisphere_frame(up);
        Light::Directional((up + 0.5 * a + 0.3 * b).normalize())
    }

    /// A point light at `point` or a directional light `towards` that direction (at most
    /// one), else [`Light::above`] `up`: the light as front ends ask for it. Refuses both at
    /// once, non-finite coordinates and a direction of no length.
    pub fn chosen(point: Option<[f64; 3]>, towards: Option<[f64; 3]>, up: DVec3) -> Result<Light> {
        let invalid = |m: &str| Err(DataError::Invalid(format!("shadow light: {m}")));
        match (point.map(DVec3::from), towards.map(DVec3::from)) {
            (Some(_), Some(_)) => invalid("a point light or a direction, not both"),
            (Some(p), None) if p.is_finite() => Ok(Light::Point(p)),
            (None, Some(d)) if d.is_finite() && d.length_squared() > 0.0 => {
                Ok(Light::Directional(d))
            }
            (None, None) => Ok(Light::above(up)),
            _ => invalid("coordinates must be finite, a direction not 0,0,0"),
        }
    }

    /// Unit direction from `point` towards the light and the distance to it (infinite for a
    /// directional light); `None` when the point is the light or the direction has no length.
    pub fn from(&self, point: DVec3) -> Option<(DVec3, f64)> {
        let (dir, t_max) = match *self {
            Light::Point(at) => (at - point, point.distance(at)),
            Light::Directional(towards) => (towards, f64::INFINITY),
        };
        Some((dir.try_normalize()?, t_max))
    }
}

/// Two unit vectors completing unit `n` to a right-handed frame, built as the traversal's ray
/// space is (`ray_space.glsl` and `effects.glsl` do the same).
pub fn hemisphere_frame(n: DVec3) -> (DVec3, DVec3) {
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = n.cross(helper).normalize();
    (u, n.cross(u))
}

/// `samples` directions over the hemisphere about +z, cosine-weighted (their mean
/// transmittance weighs directions as diffuse light does) and spread by the golden angle: a
/// fixed pattern, so every run and both the CPU and the GPU cast the same rays. In `f32`, the
/// precision the GPU receives them in.
pub fn ao_pattern(samples: u32) -> Vec<[f32; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5.0_f64.sqrt());
    (0..samples)
        .map(|i| {
            let z = (1.0 - (f64::from(i) + 0.5) / f64::from(samples)).sqrt();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * f64::from(i);
            [(r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32]
        })
        .collect()
}

/// The AO hemisphere's axis at a tet of scalar gradient `gradient`: down the gradient, towards
/// lower scalars, where dense regions are usually left (the fallback where it vanishes).
pub fn ao_normal(gradient: DVec3) -> DVec3 {
    (-gradient)
        .try_normalize()
        .unwrap_or(Vec3::from(AO_FALLBACK_NORMAL).as_dvec3())
}

/// The world directions of `pattern` about `normal`.
pub fn ao_directions(normal: DVec3, pattern: &[[f32; 3]]) -> impl Iterator<Item = DVec3> + '_ {
    let (u, v) = hemisphere_frame(normal);
    pattern.iter().map(move |p| {
        let p = Vec3::from(*p).as_dvec3();
        u * p.x + v * p.y + normal * p.z
    })
}

/// How much gradient shading applies to a stretch of mean absorption `mean_absorption` when
/// the transfer function's largest is `max_absorption`: 0 up to [`GRADIENT_THRESHOLD`] −
/// [`GRADIENT_RAMP`], 1 from the threshold, linear between; 0 where the gradient vanishes.
pub fn gradient_weight(mean_absorption: DVec3, max_absorption: f64, gradient: DVec3) -> f64 {
    if !(max_absorption > 0.0 && gradient != DVec3::ZERO) {
        return 0.0;
    }
    let relative = mean_absorption.max_element() / max_absorption;
    let (threshold, ramp) = (f64::from(GRADIENT_THRESHOLD), f64::from(GRADIENT_RAMP));
    ((relative - (threshold - ramp)) / ramp).clamp(0.0, 1.0)
}

/// What shades one stretch (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchLighting {
    /// Mean AO transmittance (1 without AO).
    pub occlusion: DVec3,
    /// Transmittance towards the light (1 without shadows).
    pub light: DVec3,
    /// Gradient-shading weight.
    pub weight: f64,
    /// The scalar gradient (any length).
    pub gradient: DVec3,
    /// Unit directions towards the light and towards the eye.
    pub to_light: DVec3,
    pub to_eye: DVec3,
}

impl StretchLighting {
    /// The factor the stretch's emission is scaled by.
    pub fn emission_factor(&self) -> DVec3 {
        let ambient = f64::from(VOLUME_AMBIENT);
        let (diffuse, highlight) = match self.gradient.try_normalize() {
            Some(n) if self.weight > 0.0 => {
                let (l, v) = (self.to_light.as_vec3(), self.to_eye.as_vec3());
                let n = shading::facing(n.as_vec3(), v);
                (
                    f64::from(n.dot(l).max(0.0)),
                    f64::from(shading::specular(n, l, v)),
                )
            }
            _ => (1.0, 0.0),
        };
        let w = self.weight;
        let diffuse = 1.0 + (diffuse - 1.0) * w;
        self.occlusion
            * (DVec3::splat(ambient)
                + (1.0 - ambient) * self.light * diffuse
                + self.light * (w * highlight))
    }
}

/// The square ground plane below a mesh, perpendicular to the up axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundPlane {
    /// Unit up axis.
    pub up: DVec3,
    /// The plane is `dot(p, up) = height`.
    pub height: f64,
}

impl GroundPlane {
    /// [`GROUND_GAP`] below the lowest corner of the world-space box `lo`–`hi` along `up`.
    pub fn below((lo, hi): (DVec3, DVec3), up: DVec3) -> GroundPlane {
        let up = up.normalize_or(DVec3::Y);
        let lowest = (0..8)
            .map(|c| {
                let corner = DVec3::new(
                    if c & 1 == 0 { lo.x } else { hi.x },
                    if c & 2 == 0 { lo.y } else { hi.y },
                    if c & 4 == 0 { lo.z } else { hi.z },
                );
                corner.dot(up)
            })
            .fold(f64::INFINITY, f64::min);
        GroundPlane {
            up,
            height: lowest - f64::from(GROUND_GAP),
        }
    }

    /// Where `origin + t dir` (unit `dir`) meets the square beyond `t_min`.
    pub fn hit(&self, origin: DVec3, dir: DVec3, t_min: f64) -> Option<f64> {
        let rate = dir.dot(self.up);
        let t = (self.height - origin.dot(self.up)) / rate;
        if !(t > t_min && t.is_finite()) {
            return None;
        }
        let p = origin + dir * t;
        let across = p - p.dot(self.up) * self.up;
        (across.abs().max_element() <= f64::from(GROUND_HALF_EXTENT)).then_some(t)
    }

    /// The plane's colour where its transmittance towards the light (unit `to_light`) is
    /// `light`: diffuse, with the volume's ambient share.
    pub fn colour(&self, to_light: DVec3, light: DVec3) -> DVec3 {
        let ambient = f64::from(VOLUME_AMBIENT);
        let diffuse = self.up.dot(to_light).max(0.0);
        Vec3::from(GROUND_ALBEDO).as_dvec3()
            * (DVec3::splat(ambient) + (1.0 - ambient) * diffuse * light)
    }
}
