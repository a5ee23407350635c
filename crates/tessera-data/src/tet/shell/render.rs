//! Emission–absorption images and shadow transmittance by shell traversal: the CPU reference
//! the GPU shell renderer will be compared with. Each tet stretch is integrated by the exact
//! integrator's per-stretch rule ([`FrontToBack::add_stretch`] over the tet's linear scalar),
//! so the only difference from [`ExactRayIntegrator`] is how the tets are found.
//!
//! [`ExactRayIntegrator`]: crate::tet::emission_absorption::ExactRayIntegrator

use glam::DVec3;
use rayon::prelude::*;

use super::layouts::{LayoutKind, TetLayout};
use super::traverse::{traverse, Ray, Step, TraversalOptions, TraversalStats};
use super::ShellMesh;
use crate::camera::OrbitCamera;
use crate::error::{DataError, Result};
use crate::image::RgbaImage;
use crate::shading::pack_rgba8;
use crate::tet::emission_absorption::{EmissionAbsorption, FrontToBack};
use crate::tet::optical::{RayStretch, WorldView};
use crate::tet::scalar_integral::{tet_linears, TetLinear};

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
    pub stats: TraversalStats,
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
            sum.add_stretch(self.optics, s_in, s_out, step.t_exit - step.t_enter);
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

    /// The light reaching `point` from `light` through the volume, per channel. Like radiance
    /// rays, shadow rays stop at 98 % opacity (the result is then below 0.02 but not exact).
    pub fn transmittance(&self, point: DVec3, light: Light, stats: &mut TraversalStats) -> DVec3 {
        let (dir, t_max) = match light {
            Light::Point(at) => (at - point, point.distance(at)),
            Light::Directional(towards) => (towards, f64::INFINITY),
        };
        let Some(dir) = dir.try_normalize() else {
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
    (width, height): (u32, u32),
    background: [f32; 3],
) -> Result<ShellRender> {
    let integrator =
        ShellIntegrator::new(shell, kind, normalized, optics, TraversalOptions::default())?;
    let mut image = RgbaImage::new(width, height);
    let mut stats = TraversalStats::default();
    if width == 0 || height == 0 {
        return Ok(ShellRender { image, stats });
    }
    let view = WorldView::new(camera, width, height);
    let background = glam::Vec3::from(background).as_dvec3();
    let row_stats: Vec<TraversalStats> = image
        .pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .map(|(y, row)| {
            let mut stats = TraversalStats::default();
            for (x, pixel) in row.iter_mut().enumerate() {
                let (dir, t_near) = view.ray(x as u32, y as u32);
                let ray = Ray {
                    origin: view.eye,
                    dir,
                    t_min: t_near,
                    t_max: f64::INFINITY,
                };
                let c = integrator.radiance(&ray, &mut stats).over(background);
                *pixel = pack_rgba8([c.x as f32, c.y as f32, c.z as f32, 1.0]);
            }
            stats
        })
        .collect();
    for s in &row_stats {
        stats.add(s);
    }
    Ok(ShellRender { image, stats })
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
