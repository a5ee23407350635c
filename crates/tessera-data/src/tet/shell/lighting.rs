//! Per-tet lighting by secondary rays (see [`super::effects`] for why per tet): each tet's
//! scalar gradient, its transmittance towards the light from its centroid, and its mean
//! transmittance over the AO hemisphere, each marched by the same traversal as pixel rays, so
//! the volume shadows and occludes itself.

use glam::DVec3;
use rayon::prelude::*;

use super::effects::{ao_directions, ao_normal, ao_pattern, SecondaryStats, ShellEffects};
use super::render::{Light, ShellIntegrator};
use super::traverse::{Ray, TraversalStats};

/// The lighting of every tet; each list is empty where its effect is off.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TetLighting {
    /// The scalar gradient per tet (for gradient shading and AO).
    pub gradients: Vec<DVec3>,
    /// Transmittance from the centroid towards the light, per channel (shadows).
    pub light: Vec<DVec3>,
    /// Mean transmittance over the AO rays, per channel (AO).
    pub occlusion: Vec<DVec3>,
}

impl TetLighting {
    /// Casts the secondary rays `effects` asks for from every tet, counting them in `stats`.
    pub fn compute(
        integrator: &ShellIntegrator,
        effects: &ShellEffects,
        stats: &mut SecondaryStats,
    ) -> TetLighting {
        let tets = 0..integrator.tet_count();
        let gradients: Vec<DVec3> = if effects.needs_gradients() {
            tets.clone().map(|t| integrator.gradient(t)).collect()
        } else {
            Vec::new()
        };
        let mut per_tet = |what: &(dyn Fn(usize, &mut SecondaryStats) -> DVec3 + Sync)| {
            let (values, counts): (Vec<DVec3>, Vec<SecondaryStats>) = tets
                .clone()
                .into_par_iter()
                .map(|t| {
                    let mut s = SecondaryStats::default();
                    (what(t, &mut s), s)
                })
                .unzip();
            counts.iter().for_each(|c| stats.add(c));
            values
        };
        let light = match effects.shadows {
            Some(light) => per_tet(&|t, s| {
                let point = integrator.centroid(t);
                shadow(integrator, point, light, s)
            }),
            None => Vec::new(),
        };
        let occlusion = match effects.ambient_occlusion {
            Some(ao) => {
                let pattern = ao_pattern(ao.samples);
                per_tet(&|t, s| {
                    let origin = integrator.centroid(t);
                    let mut sum = DVec3::ZERO;
                    for dir in ao_directions(ao_normal(gradients[t]), &pattern) {
                        let ray = Ray {
                            origin,
                            dir,
                            t_min: 0.0,
                            t_max: f64::from(ao.radius),
                        };
                        s.ao_rays += 1;
                        sum += secondary(integrator, &ray, s);
                    }
                    sum / f64::from(ao.samples)
                })
            }
            None => Vec::new(),
        };
        TetLighting {
            gradients,
            light,
            occlusion,
        }
    }
}

/// The transmittance from `point` towards `light`, counted as a shadow ray.
pub(crate) fn shadow(
    integrator: &ShellIntegrator,
    point: DVec3,
    light: Light,
    stats: &mut SecondaryStats,
) -> DVec3 {
    stats.shadow_rays += 1;
    let Some((dir, t_max)) = light.from(point) else {
        return DVec3::ONE;
    };
    let ray = Ray {
        origin: point,
        dir,
        t_min: 0.0,
        t_max,
    };
    secondary(integrator, &ray, stats)
}

/// The transmittance along a secondary ray, its traversal counted in `stats`.
fn secondary(integrator: &ShellIntegrator, ray: &Ray, stats: &mut SecondaryStats) -> DVec3 {
    let mut traversal = TraversalStats::default();
    let t = integrator.radiance(ray, &mut traversal).transmittance;
    stats.steps += traversal.steps;
    stats.guard_hits += traversal.guard_hits();
    t
}
