//! Tests of front-to-back emission–absorption and the exact per-ray integrator.
use super::*;
use crate::camera::OrbitCamera;
use crate::tet::optical::WorldView;
use crate::tet::procedural::box_mesh;
use crate::tet::scalar_integral::{integrate_scalar, normalized_scalars};

fn optics(density: f32) -> EmissionAbsorption {
    EmissionAbsorption::new(&TransferFunction::preset("cool-warm").unwrap(), density)
}

#[test]
fn a_homogeneous_stretch_follows_beer_lambert_and_the_emission_closed_form() {
    let optics = optics(2.0);
    let mut sum = FrontToBack::default();
    sum.add_stretch(&optics, 0.4, 0.4, 0.3);
    let tau = optics.absorption.value(0.4) * 0.3;
    let e = optics.emission.value(0.4) * 0.3;
    for c in 0..3 {
        let t = (-tau[c]).exp();
        assert!((sum.transmittance[c] - t).abs() < 1e-12);
        assert!((sum.colour[c] - e[c] * (1.0 - t) / tau[c]).abs() < 1e-12);
    }
    // Splitting a homogeneous stretch changes nothing.
    let mut halves = FrontToBack::default();
    halves.add_stretch(&optics, 0.4, 0.4, 0.1);
    halves.add_stretch(&optics, 0.4, 0.4, 0.2);
    assert!((halves.colour - sum.colour).abs().max_element() < 1e-12);
    assert!(
        (halves.transmittance - sum.transmittance)
            .abs()
            .max_element()
            < 1e-12
    );
    // A stretch without length adds nothing.
    let before = sum;
    sum.add_stretch(&optics, 0.9, 0.1, 0.0);
    assert_eq!(sum, before);
}

#[test]
fn opacity_counts_the_most_transparent_channel() {
    let sum = FrontToBack {
        colour: DVec3::ZERO,
        transmittance: DVec3::new(0.01, 0.015, 0.03),
    };
    assert!((sum.opacity() - 0.97).abs() < 1e-12);
    assert!(!sum.is_opaque());
    let sum = FrontToBack {
        transmittance: DVec3::splat(0.019),
        ..sum
    };
    assert!(sum.is_opaque());
}

/// Pure absorption front to back is Beer–Lambert of interval shading's optical depth: the
/// per-ray integrator against [`integrate_scalar`], pixel by pixel, on the same rays.
#[test]
fn absorption_alone_matches_the_scalar_integrator() {
    let mesh = box_mesh(3);
    let normalized = normalized_scalars(&mesh, None, "box").unwrap();
    let mut optics = optics(1.5);
    optics
        .emission
        .values
        .iter_mut()
        .for_each(|v| *v = [0.0; 3]);
    let camera = OrbitCamera::default();
    let (w, h) = (24, 18);
    let depth = integrate_scalar(
        &mesh,
        &normalized,
        &camera,
        (w, h),
        &optics.absorption,
        ScalarMode::Absorption,
    );
    let exact = ExactRayIntegrator::new(&mesh, &normalized);
    let view = WorldView::new(&camera, w, h);
    let mut covered = 0;
    for y in 0..h {
        for x in 0..w {
            let (dir, near) = view.ray(x, y);
            let sum = exact.integrate(&optics, view.eye, dir, (near, f64::INFINITY), false);
            let d = depth[(y * w + x) as usize];
            for (c, depth) in d.iter().enumerate() {
                let want = (-f64::from(*depth)).exp();
                assert!(
                    (sum.transmittance[c] - want).abs() < 1e-5,
                    "pixel ({x}, {y}) channel {c}: {} vs {want}",
                    sum.transmittance[c]
                );
            }
            assert_eq!(sum.colour, DVec3::ZERO);
            covered += usize::from(d[0] > 0.0);
        }
    }
    assert!(covered > 100, "{covered} pixels see the box");
}

#[test]
fn early_termination_stops_once_opaque() {
    let mesh = box_mesh(4);
    let normalized = normalized_scalars(&mesh, None, "box").unwrap();
    let dense = optics(400.0);
    let exact = ExactRayIntegrator::new(&mesh, &normalized);
    let (origin, dir) = (DVec3::new(-1.0, 0.01, 0.02), DVec3::X);
    let stopped = exact.integrate(&dense, origin, dir, (0.0, f64::INFINITY), true);
    let full = exact.integrate(&dense, origin, dir, (0.0, f64::INFINITY), false);
    assert!(stopped.is_opaque());
    assert!(stopped.transmittance.max_element() > full.transmittance.max_element());
    assert!((stopped.colour - full.colour).abs().max_element() < 0.05);
}
