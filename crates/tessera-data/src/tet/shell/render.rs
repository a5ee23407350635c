//! Emission–absorption images and shadow transmittance by shell traversal: the CPU reference
//! the GPU shell renderer will be compared with. Each tet stretch is integrated by the exact
//! integrator's per-stretch rule ([`FrontToBack::add_stretch`] over the tet's linear scalar),
//! so the only difference from [`ExactRayIntegrator`] is how the tets are found. With
//! [`ShellEffects`] each stretch's emission is scaled by its tet's lighting
//! ([`super::effects`], [`super::lighting`]) and the ground plane ends pixel rays.
//!
//! [`ExactRayIntegrator`]: crate::tet::emission_absorption::ExactRayIntegrator

use glam::DVec3;
use rayon::prelude::*;

use super::effects::{gradient_weight, GroundPlane, SecondaryStats, ShellEffects, StretchLighting};
use super::layouts::{LayoutKind, TetLayout};
use super::lighting::{shadow, TetLighting};
use super::traverse::{traverse, Ray, Step, TraversalOptions, TraversalStats};
use super::ShellMesh;
use crate::camera::OrbitCamera;
use crate::error::{DataError, Result};
use crate::image::RgbaImage;
use crate::shading::pack_rgba8;
use crate::tet::emission_absorption::{EmissionAbsorption, FrontToBack};
use crate::tet::optical::{RayStretch, WorldView};
use crate::tet::scalar_integral::{tet_linears, TetLinear};
use crate::view::View;

/// A light for shadow rays, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// At a point: the shadow ray ends there.
    Point(DVec3),
    /// Infinitely far in this direction (towards the light).
    Directional(DVec3),
}

/// An image and what its rays' traversals counted.
#[derive(Clone, Debug, PartialEq)]
pub struct ShellRender {
    pub image: RgbaImage,
    /// Pixel rays' traversals.
    pub stats: TraversalStats,
    /// Secondary rays (none without effects).
    pub secondary: SecondaryStats,
    /// The per-tet lighting the effects computed.
    pub lighting: TetLighting,
}

/// A stretch of a ray inside one tet, as the effects shade it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LitStretch {
    pub tet: usize,
    /// World-space middle of the stretch.
    pub midpoint: DVec3,
    /// Unit direction of the ray.
    pub dir: DVec3,
    /// The absorption table's mean over the stretch's scalar run.
    pub mean_absorption: DVec3,
}

/// A shell mesh with a layout, its linear scalars and the optical model: everything a ray
/// needs, for per-ray comparisons and secondary rays.
pub struct ShellIntegrator<'a> {
    shell: &'a ShellMesh,
    layout: Box<dyn TetLayout>,
    linears: Vec<TetLinear>,
    optics: &'a EmissionAbsorption,
    options: TraversalOptions,
}

impl<'a> ShellIntegrator<'a> {
    /// `normalized`: one scalar in [0, 1] per vertex of `shell.mesh` (Morton order).
    pub fn new(
        shell: &'a ShellMesh,
        kind: LayoutKind,
        normalized: &[f32],
        optics: &'a EmissionAbsorption,
        options: TraversalOptions,
    ) -> Result<ShellIntegrator<'a>> {
        if normalized.len() != shell.mesh.vertices.len() {
            return Err(DataError::Invalid(format!(
                "shell traversal: {} scalars for {} vertices",
                normalized.len(),
                shell.mesh.vertices.len()
            )));
        }
        Ok(ShellIntegrator {
            shell,
            layout: shell.layout(kind),
            linears: tet_linears(&shell.mesh, normalized),
            optics,
            options,
        })
    }

    /// Emission–absorption along `ray`, front to back, with early termination.
    pub fn radiance(&self, ray: &Ray, stats: &mut TraversalStats) -> FrontToBack {
        self.lit_radiance(ray, stats, |_| DVec3::ONE)
    }

    /// [`ShellIntegrator::radiance`] with each stretch's emission scaled by what `light`
    /// returns for it.
    pub fn lit_radiance(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
        light: impl Fn(&LitStretch) -> DVec3,
    ) -> FrontToBack {
        let mut sum = FrontToBack::default();
        // Step distances are along the unit direction.
        let dir = ray.dir.normalize_or_zero();
        let mut add = |_: usize, step: &Step| {
            let stretch = RayStretch {
                eye: ray.origin,
                dir,
                enter: step.t_enter,
                exit: step.t_exit,
            };
            let (s_in, s_out) = self.linears[step.tet as usize].at_ends(&stretch);
            let lit = LitStretch {
                tet: step.tet as usize,
                midpoint: ray.origin + dir * (0.5 * (step.t_enter + step.t_exit)),
                dir,
                mean_absorption: self.optics.absorption.average(s_in, s_out),
            };
            let length = step.t_exit - step.t_enter;
            sum.add_lit_stretch(self.optics, s_in, s_out, length, light(&lit));
            !sum.is_opaque()
        };
        traverse(
            self.shell,
            &*self.layout,
            ray,
            &self.options,
            stats,
            &mut add,
        );
        sum
    }

    pub fn tet_count(&self) -> usize {
        self.linears.len()
    }

    /// The gradient of tet `tet`'s linear scalar (zero for a flat tet).
    pub fn gradient(&self, tet: usize) -> DVec3 {
        self.linears[tet].gradient()
    }

    /// The mean of tet `tet`'s corners, in world space.
    pub fn centroid(&self, tet: usize) -> DVec3 {
        let world = self.shell.world();
        self.shell.mesh.tets[tet]
            .iter()
            .map(|&v| world[v as usize])
            .sum::<DVec3>()
            * 0.25
    }

    /// The light reaching `point` from `light` through the volume, per channel. Like radiance
    /// rays, shadow rays stop at 98 % opacity (the result is then below 0.02 but not exact).
    pub fn transmittance(&self, point: DVec3, light: Light, stats: &mut TraversalStats) -> DVec3 {
        let Some((dir, t_max)) = light.from(point) else {
            return DVec3::ONE;
        };
        let ray = Ray {
            origin: point,
            dir,
            t_min: 0.0,
            t_max,
        };
        self.radiance(&ray, stats).transmittance
    }
}

/// Emission–absorption image of `shell` with scalars `normalized` (one in [0, 1] per vertex
/// of `shell.mesh`) through `optics`, seen by `camera` at `size`, over `background`. Pixel
/// rays and placement follow interval shading's reference ([`crate::tet::optical`]): rays
/// start at the near plane.
pub fn render_shell_reference(
    shell: &ShellMesh,
    kind: LayoutKind,
    normalized: &[f32],
    optics: &EmissionAbsorption,
    camera: &OrbitCamera,
    size: (u32, u32),
    background: [f32; 3],
) -> Result<ShellRender> {
    let scene = ShellScene {
        shell,
        kind,
        normalized,
        optics,
        effects: &ShellEffects::default(),
    };
    render_shell_effects_reference(&scene, camera, size, background)
}

/// What a shell traversal image shows: a mesh in a layout, its scalars (one in [0, 1] per
/// vertex of `shell.mesh`), the optical model and the effects.
#[derive(Clone, Copy)]
pub struct ShellScene<'a> {
    pub shell: &'a ShellMesh,
    pub kind: LayoutKind,
    pub normalized: &'a [f32],
    pub optics: &'a EmissionAbsorption,
    pub effects: &'a ShellEffects,
}

/// [`render_shell_reference`] with `scene.effects` ([`super::effects`]): per-tet lighting by
/// secondary rays first, then each pixel ray's stretches shaded with it, ending at the ground
/// plane where shadows put one (lit by its own shadow ray). Without effects the image is
/// exactly [`render_shell_reference`]'s.
pub fn render_shell_effects_reference(
    scene: &ShellScene,
    camera: &OrbitCamera,
    (width, height): (u32, u32),
    background: [f32; 3],
) -> Result<ShellRender> {
    let integrator = ShellIntegrator::new(
        scene.shell,
        scene.kind,
        scene.normalized,
        scene.optics,
        TraversalOptions::default(),
    )?;
    let effects = scene.effects;
    let mut image = RgbaImage::new(width, height);
    let mut stats = TraversalStats::default();
    let mut secondary = SecondaryStats::default();
    let lighting = TetLighting::compute(&integrator, effects, &mut secondary);
    if width == 0 || height == 0 {
        return Ok(ShellRender {
            image,
            stats,
            secondary,
            lighting,
        });
    }
    let view = WorldView::new(camera, width, height);
    let headlight = View::of_unit_box(camera, (width, height)).light.as_dvec3();
    let light = effects.light(headlight);
    let ground = effects
        .shadows
        .map(|_| GroundPlane::below(scene.shell.world_bounds(), camera.up.vector().as_dvec3()));
    let shader = StretchShader {
        effects,
        lighting: &lighting,
        light,
        max_absorption: scene.optics.max_absorption(),
    };
    let background = glam::Vec3::from(background).as_dvec3();
    let row_stats: Vec<(TraversalStats, SecondaryStats)> = image
        .pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .map(|(y, row)| {
            let mut stats = TraversalStats::default();
            let mut secondary = SecondaryStats::default();
            for (x, pixel) in row.iter_mut().enumerate() {
                let (dir, t_near) = view.ray(x as u32, y as u32);
                let mut ray = Ray {
                    origin: view.eye,
                    dir,
                    t_min: t_near,
                    t_max: f64::INFINITY,
                };
                let mut behind = background;
                // The ground ends the ray and shows behind the volume.
                if let Some((plane, t)) =
                    ground.and_then(|g| Some((g, g.hit(view.eye, dir, t_near)?)))
                {
                    ray.t_max = t;
                    let point = view.eye + dir * t;
                    let to_light = light.from(point).map_or(DVec3::ZERO, |l| l.0);
                    let lit = shadow(&integrator, point, light, &mut secondary);
                    behind = plane.colour(to_light, lit);
                }
                let c = if effects.any() {
                    integrator.lit_radiance(&ray, &mut stats, |s| shader.factor(s))
                } else {
                    integrator.radiance(&ray, &mut stats)
                }
                .over(behind);
                *pixel = pack_rgba8([c.x as f32, c.y as f32, c.z as f32, 1.0]);
            }
            (stats, secondary)
        })
        .collect();
    for (s, t) in &row_stats {
        stats.add(s);
        secondary.add(t);
    }
    Ok(ShellRender {
        image,
        stats,
        secondary,
        lighting,
    })
}

/// The emission factor of each stretch from the per-tet lighting.
struct StretchShader<'a> {
    effects: &'a ShellEffects,
    lighting: &'a TetLighting,
    light: Light,
    max_absorption: f64,
}

impl StretchShader<'_> {
    fn factor(&self, s: &LitStretch) -> DVec3 {
        let per_tet = |list: &[DVec3]| list.get(s.tet).copied().unwrap_or(DVec3::ONE);
        let gradient = if self.effects.gradient {
            self.lighting.gradients[s.tet]
        } else {
            DVec3::ZERO
        };
        StretchLighting {
            occlusion: per_tet(&self.lighting.occlusion),
            light: per_tet(&self.lighting.light),
            weight: gradient_weight(s.mean_absorption, self.max_absorption, gradient),
            gradient,
            to_light: self.light.from(s.midpoint).map_or(DVec3::ZERO, |l| l.0),
            to_eye: -s.dir,
        }
        .emission_factor()
    }
}

/// The fraction of `light` that reaches `point` (world space) through the volume of
/// `shell` with scalars `normalized` and model `optics`, per channel, and what the shadow
/// ray's traversal counted.
pub fn shadow_transmittance(
    shell: &ShellMesh,
    kind: LayoutKind,
    normalized: &[f32],
    optics: &EmissionAbsorption,
    point: DVec3,
    light: Light,
) -> Result<(DVec3, TraversalStats)> {
    let integrator =
        ShellIntegrator::new(shell, kind, normalized, optics, TraversalOptions::default())?;
    let mut stats = TraversalStats::default();
    let t = integrator.transmittance(point, light, &mut stats);
    Ok((t, stats))
}
