//! Tests of the secondary-ray effects: the sample pattern, exact gradients, per-tet shadow and
//! AO transmittance against the exact integrator, and images where shadows and AO darken what
//! they should and nothing else.
use glam::DVec3;

use super::test_meshes::two_boxes;
use super::*;
use crate::camera::OrbitCamera;
use crate::tet::emission_absorption::{EmissionAbsorption, ExactRayIntegrator};
use crate::tet::procedural::box_mesh;
use crate::tet::scalar_integral::normalized_scalars;
use crate::transfer::TransferFunction;

/// Per-ray transmittance agrees this closely with the exact integrator (as in render_tests).
const EA_TOLERANCE: f64 = 1e-9;
/// A mean over AO rays that end inside tets (clipped where the two integrators compute the
/// scalar by different formulas) agrees a little less closely.
const AO_TOLERANCE: f64 = 1e-8;

fn optics(density: f32) -> EmissionAbsorption {
    EmissionAbsorption::new(&TransferFunction::preset("cool-warm").unwrap(), density)
}

fn scalars(shell: &ShellMesh) -> Vec<f32> {
    normalized_scalars(&shell.mesh, None, "effects test").unwrap()
}

fn scene<'a>(
    shell: &'a ShellMesh,
    normalized: &'a [f32],
    optics: &'a EmissionAbsorption,
    effects: &'a ShellEffects,
) -> ShellScene<'a> {
    ShellScene {
        shell,
        kind: LayoutKind::Tet20,
        normalized,
        optics,
        effects,
    }
}

#[test]
fn the_ao_pattern_is_fixed_unit_and_over_the_hemisphere() {
    for n in [1, 4, 16, MAX_AO_SAMPLES] {
        let pattern = ao_pattern(n);
        assert_eq!(pattern, ao_pattern(n), "reproducible");
        assert_eq!(pattern.len(), n as usize);
        let mut mean = DVec3::ZERO;
        for p in &pattern {
            let d = glam::Vec3::from(*p).as_dvec3();
            assert!((d.length() - 1.0).abs() < 1e-6, "{d}");
            assert!(d.z > 0.0, "{d}");
            mean += d / f64::from(n);
        }
        // Cosine-weighted: the mean leans on the axis (2/3 for a continuous pattern) and the
        // golden angle spreads the rest evenly around it.
        if n >= 16 {
            assert!((mean.z - 2.0 / 3.0).abs() < 0.02, "{n}: {mean}");
            assert!(mean.truncate().length() < 0.05, "{n}: {mean}");
        }
    }
    let normal = DVec3::new(0.3, -0.5, 0.8).normalize();
    for d in ao_directions(normal, &ao_pattern(8)) {
        assert!(d.dot(normal) > 0.0);
        assert!((d.length() - 1.0).abs() < 1e-6);
    }
    assert_eq!(ao_normal(DVec3::ZERO), DVec3::Y);
    assert_eq!(ao_normal(DVec3::new(0.0, 0.0, 2.0)), -DVec3::Z);
}

#[test]
fn tet_gradients_are_exact_for_a_linear_scalar() {
    let mut mesh = box_mesh(2);
    let slope = DVec3::new(2.0, 3.0, -1.0);
    mesh.scalars = Some(
        mesh.vertices
            .iter()
            .map(|p| glam::Vec3::from(*p).as_dvec3().dot(slope) as f32)
            .collect(),
    );
    let shell = ShellMesh::build(&mesh).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(1.0);
    let integrator = ShellIntegrator::new(
        &shell,
        LayoutKind::Tet32,
        &normalized,
        &optics,
        TraversalOptions::default(),
    )
    .unwrap();
    // World = mesh × scale, normalized = (s − lo) / (hi − lo): both divide the slope.
    let (lo, hi) = crate::tet::scalar_integral::scalar_range(&shell.mesh).unwrap();
    let want = slope / (f64::from(shell.frame.scale) * f64::from(hi - lo));
    for t in 0..integrator.tet_count() {
        let got = integrator.gradient(t);
        assert!(
            (got - want).length() < 1e-5 * want.length(),
            "tet {t}: {got} vs {want}"
        );
    }
}

#[test]
fn per_tet_shadow_and_ao_rays_see_what_the_exact_integrator_sees() {
    let shell = ShellMesh::build(&two_boxes()).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(8.0);
    let exact = ExactRayIntegrator::new(&shell.mesh, &normalized);
    let integrator = ShellIntegrator::new(
        &shell,
        LayoutKind::Tet16,
        &normalized,
        &optics,
        TraversalOptions::default(),
    )
    .unwrap();
    let ao = AmbientOcclusion::new(6, 0.3).unwrap();
    for light in [
        Light::Directional(DVec3::new(0.9, 0.4, 0.2)),
        Light::Point(DVec3::new(0.02, 0.03, 0.01)),
    ] {
        let effects = ShellEffects {
            shadows: Some(light),
            ambient_occlusion: Some(ao),
            gradient: true,
        };
        let mut stats = SecondaryStats::default();
        let lighting = TetLighting::compute(&integrator, &effects, &mut stats);
        let tets = integrator.tet_count();
        assert_eq!(stats.shadow_rays, tets as u64);
        assert_eq!(stats.ao_rays, 6 * tets as u64);
        assert_eq!(stats.guard_hits, 0);
        assert!(stats.steps > stats.shadow_rays);
        let (mut shadowed, mut occluded) = (0, 0);
        for t in 0..tets {
            let c = integrator.centroid(t);
            let (dir, t_max) = light.from(c).unwrap();
            let want = exact
                .integrate(&optics, c, dir, (0.0, t_max), true)
                .transmittance;
            let got = lighting.light[t];
            assert!(
                (got - want).abs().max_element() < EA_TOLERANCE,
                "tet {t}: {got} vs {want}"
            );
            shadowed += usize::from(got.max_element() < 0.9);
            let mut sum = DVec3::ZERO;
            let pattern = ao_pattern(ao.samples);
            for d in ao_directions(ao_normal(lighting.gradients[t]), &pattern) {
                sum += exact
                    .integrate(&optics, c, d, (0.0, f64::from(ao.radius)), true)
                    .transmittance;
            }
            let want = sum / f64::from(ao.samples);
            let got = lighting.occlusion[t];
            assert!(
                (got - want).abs().max_element() < AO_TOLERANCE,
                "AO tet {t}: {got} vs {want}"
            );
            occluded += usize::from(got.max_element() < 0.9);
        }
        assert!(
            shadowed > 0 && occluded > 0,
            "{light:?}: {shadowed} shadowed, {occluded} occluded"
        );
    }
}

#[test]
fn the_volume_shadows_the_ground_and_itself() {
    let shell = ShellMesh::build(&box_mesh(3)).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(30.0);
    // The sun straight above.
    let camera = OrbitCamera {
        elevation_deg: 30.0,
        distance: 2.2,
        ..OrbitCamera::default()
    };
    let size = (48, 48);
    let lit_effects = ShellEffects {
        shadows: Some(Light::Directional(DVec3::Y)),
        ..ShellEffects::default()
    };
    let background = [0.0, 0.0, 0.0];
    let with = render_shell_effects_reference(
        &scene(&shell, &normalized, &optics, &lit_effects),
        &camera,
        size,
        background,
    )
    .unwrap();
    let without = render_shell_reference(
        &shell,
        LayoutKind::Tet20,
        &normalized,
        &optics,
        &camera,
        size,
        background,
    )
    .unwrap();
    assert_eq!(without.secondary, SecondaryStats::default());
    assert!(with.secondary.shadow_rays > shell.mesh.tets.len() as u64);
    assert_eq!(with.secondary.guard_hits, 0);
    // The box's lowest tets lie in the shadow of those above them: their light is dimmer.
    let lighting = &with.lighting;
    let integrator = ShellIntegrator::new(
        &shell,
        LayoutKind::Tet20,
        &normalized,
        &optics,
        TraversalOptions::default(),
    )
    .unwrap();
    let height = |t: usize| integrator.centroid(t).y;
    let (mut top, mut bottom) = (DVec3::ZERO, DVec3::ZERO);
    let (mut n_top, mut n_bottom) = (0.0, 0.0);
    for t in 0..integrator.tet_count() {
        if height(t) > 0.25 {
            top += lighting.light[t];
            n_top += 1.0;
        } else if height(t) < -0.25 {
            bottom += lighting.light[t];
            n_bottom += 1.0;
        }
    }
    let (top, bottom) = (top / n_top, bottom / n_bottom);
    assert!(
        bottom.max_element() < 0.75 * top.min_element(),
        "top {top}, bottom {bottom}"
    );
}

#[test]
fn the_ground_under_the_volume_is_darker_than_beside_it() {
    let shell = ShellMesh::build(&box_mesh(2)).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(40.0);
    let size = (64, 48);
    let camera = OrbitCamera {
        azimuth_deg: 20.0,
        elevation_deg: 35.0,
        distance: 2.4,
        ..OrbitCamera::default()
    };
    let light = Light::Directional(DVec3::new(0.0, 1.0, 0.0));
    let effects = ShellEffects {
        shadows: Some(light),
        ..ShellEffects::default()
    };
    let render = render_shell_effects_reference(
        &scene(&shell, &normalized, &optics, &effects),
        &camera,
        size,
        [0.0; 3],
    )
    .unwrap();
    let plane = GroundPlane::below(shell.world_bounds(), DVec3::Y);
    assert!((plane.height - (-0.5 - f64::from(GROUND_GAP))).abs() < 1e-6);
    // Shadow rays from ground points straight up: under the box they cross it.
    let integrator = ShellIntegrator::new(
        &shell,
        LayoutKind::Tet20,
        &normalized,
        &optics,
        TraversalOptions::default(),
    )
    .unwrap();
    let mut stats = TraversalStats::default();
    let under = integrator.transmittance(DVec3::new(0.1, plane.height, 0.1), light, &mut stats);
    let beside = integrator.transmittance(DVec3::new(0.8, plane.height, 0.1), light, &mut stats);
    assert_eq!(beside, DVec3::ONE);
    assert!(under.max_element() < 0.5, "{under}");
    let shadowed = plane.colour(DVec3::Y, under);
    let lit = plane.colour(DVec3::Y, beside);
    assert!(shadowed.x < 0.7 * lit.x, "{shadowed} vs {lit}");
    // Somewhere in the image a pixel shows lit ground, and the image differs from the one
    // without the plane.
    let lit_byte = (lit.x * 255.0).round() as u32;
    assert!(render.image.pixels.iter().any(|&p| (p & 0xff) == lit_byte));
}

#[test]
fn ao_and_gradient_shading_change_only_what_emits() {
    let shell = ShellMesh::build(&box_mesh(3)).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(6.0);
    let camera = OrbitCamera {
        distance: 2.0,
        ..OrbitCamera::default()
    };
    let size = (32, 24);
    let plain = render_shell_reference(
        &shell,
        LayoutKind::Tet20,
        &normalized,
        &optics,
        &camera,
        size,
        [0.0; 3],
    )
    .unwrap();
    // Effects that shade nothing give the plain image exactly.
    let no_effects = render_shell_effects_reference(
        &scene(&shell, &normalized, &optics, &ShellEffects::default()),
        &camera,
        size,
        [0.0; 3],
    )
    .unwrap();
    assert_eq!(no_effects.image, plain.image);
    let ao = ShellEffects {
        ambient_occlusion: Some(AmbientOcclusion::new(8, 0.2).unwrap()),
        ..ShellEffects::default()
    };
    let occluded = render_shell_effects_reference(
        &scene(&shell, &normalized, &optics, &ao),
        &camera,
        size,
        [0.0; 3],
    )
    .unwrap();
    assert_eq!(occluded.secondary.ao_rays, 8 * shell.mesh.tets.len() as u64);
    // AO only takes light away: no pixel gets brighter, many darker.
    let (mut darker, mut brighter) = (0, 0);
    for (a, b) in occluded.image.pixels.iter().zip(&plain.image.pixels) {
        for c in 0..3 {
            let (a, b) = ((a >> (8 * c)) & 0xff, (b >> (8 * c)) & 0xff);
            darker += usize::from(a + 1 < b);
            brighter += usize::from(a > b);
        }
    }
    assert_eq!(brighter, 0);
    assert!(darker > 100, "{darker}");
    let gradient = ShellEffects {
        gradient: true,
        ..ShellEffects::default()
    };
    let shaded = render_shell_effects_reference(
        &scene(&shell, &normalized, &optics, &gradient),
        &camera,
        size,
        [0.0; 3],
    )
    .unwrap();
    assert_eq!(
        shaded.secondary,
        SecondaryStats::default(),
        "gradients cast no rays"
    );
    assert_ne!(shaded.image, plain.image);
}

#[test]
fn the_shading_model_is_the_identity_without_light_or_gradient() {
    let neutral = StretchLighting {
        occlusion: DVec3::ONE,
        light: DVec3::ONE,
        weight: 0.0,
        gradient: DVec3::X,
        to_light: DVec3::Y,
        to_eye: DVec3::Z,
    };
    assert!((neutral.emission_factor() - DVec3::ONE).abs().max_element() < 1e-12);
    // Full gradient shading, lit head on: ambient plus full diffuse plus the highlight.
    let head_on = StretchLighting {
        weight: 1.0,
        gradient: DVec3::Z,
        to_light: DVec3::Z,
        ..neutral
    };
    let f = head_on.emission_factor();
    let want = 1.0 + f64::from(crate::shading::SPECULAR_STRENGTH);
    assert!((f.x - want).abs() < 1e-6, "{f}");
    // Lit edge on: the ambient share only.
    let edge_on = StretchLighting {
        to_light: DVec3::X,
        gradient: DVec3::Z,
        weight: 1.0,
        ..neutral
    };
    let f = edge_on.emission_factor();
    assert!((f.x - f64::from(VOLUME_AMBIENT)).abs() < 1e-6, "{f}");
    // In full shadow: the ambient share only, scaled by AO.
    let dark = StretchLighting {
        light: DVec3::ZERO,
        occlusion: DVec3::splat(0.5),
        ..neutral
    };
    let f = dark.emission_factor();
    assert!((f.x - 0.5 * f64::from(VOLUME_AMBIENT)).abs() < 1e-12, "{f}");
    assert_eq!(gradient_weight(DVec3::splat(1.0), 1.0, DVec3::ZERO), 0.0);
    assert_eq!(gradient_weight(DVec3::splat(1.0), 1.0, DVec3::X), 1.0);
    assert_eq!(gradient_weight(DVec3::splat(0.1), 1.0, DVec3::X), 0.0);
    let mid = f64::from(GRADIENT_THRESHOLD - 0.5 * GRADIENT_RAMP);
    assert!((gradient_weight(DVec3::splat(mid), 1.0, DVec3::X) - 0.5).abs() < 1e-6);
}

#[test]
fn ao_settings_are_checked() {
    assert!(AmbientOcclusion::new(0, 0.1).is_err());
    assert!(AmbientOcclusion::new(MAX_AO_SAMPLES + 1, 0.1).is_err());
    assert!(AmbientOcclusion::new(4, 0.0).is_err());
    assert!(AmbientOcclusion::new(4, f32::NAN).is_err());
    assert!(AmbientOcclusion::new(4, 0.2).is_ok());
    let Light::Directional(d) = Light::above(DVec3::Y) else {
        panic!("a directional light")
    };
    assert!(d.y > 0.7 && (d.length() - 1.0).abs() < 1e-12, "{d}");
}
