//! Tests of `functions` (sphere, heart and the generic normal).
use super::*;

/// `n × n` grid over a domain, edges included.
pub(crate) fn grid(domain: &ParamDomain, n: usize) -> Vec<(f32, f32)> {
    let mut out = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let s = i as f32 / (n - 1) as f32;
            let t = j as f32 / (n - 1) as f32;
            let u = domain.u[0] + (domain.u[1] - domain.u[0]) * s;
            let v = domain.v[0] + (domain.v[1] - domain.v[0]) * t;
            out.push((u.min(domain.u[1]), v.min(domain.v[1])));
        }
    }
    out
}

/// Listing 1 of paper E, line by line, with the sphere line of the authors' released shader.
fn listing_1(u: f32, v: f32) -> Vec3 {
    let pi: f32 = "3.14159265359".parse().unwrap();
    let mut p = Vec3::new(u.sin() * v.cos(), u.cos(), u.sin() * v.sin());
    if u < pi / 2.0 {
        p.y *= 1.0 - ((p.x * pi * 0.7).abs().sqrt().sqrt().cos() * 0.8);
    } else {
        p.x *= u.sin() * u.sin();
    }
    p *= Vec3::new(0.9, 1.0, 0.4);
    p
}

#[test]
fn sphere_points_have_unit_norm() {
    let f = ParamFunction::Sphere;
    for (u, v) in grid(&f.domain(), 41) {
        let p = f.position(u, v);
        assert!((p.length() - 1.0).abs() < 1e-6, "({u}, {v}) -> {p}");
    }
    assert!((sphere(0.0, 1.0) - Vec3::Z).length() < 1e-7);
}

#[test]
fn heart_matches_listing_1() {
    let f = ParamFunction::Heart;
    for (u, v) in grid(&f.domain(), 37) {
        assert_eq!(f.position(u, v), listing_1(u, v), "({u}, {v})");
    }
    // Both branches of the listing's `if` are exercised by the grid; check one point by hand:
    // u = π/4 (upper branch), v = 0: p = (sin, cos, 0)·(0.9, 1, 0.4), y scaled by the dent.
    let u = std::f32::consts::FRAC_PI_4;
    let x = u.sin();
    let dent = 1.0 - (x * std::f32::consts::PI * 0.7).sqrt().sqrt().cos() * 0.8;
    let expected = Vec3::new(0.9 * x, u.cos() * dent, 0.0);
    assert!((heart(u, 0.0) - expected).length() < 1e-6);
}

/// Why the listing's printed first line is not used: it folds the surface onto itself.
#[test]
fn printed_listing_start_is_folded() {
    let printed = |u: f32, v: f32| Vec3::new(u.sin() * u.cos(), u.cos(), u.sin() * v.cos());
    let (u, v) = (1.0_f32, 0.8_f32);
    assert_eq!(printed(u, v), printed(u, std::f32::consts::TAU - v));
    assert_ne!(heart(u, v), heart(u, std::f32::consts::TAU - v));
}

#[test]
fn sphere_normals_are_radial_including_poles() {
    let f = ParamFunction::Sphere;
    for (u, v) in grid(&f.domain(), 33) {
        let n = f
            .normal(u, v)
            .unwrap_or_else(|| panic!("no normal at ({u}, {v})"));
        let p = f.position(u, v);
        assert!(n.dot(p) > 1.0 - 2e-5, "({u}, {v}): n = {n}, p = {p}");
    }
    let north = f.normal(0.0, 2.0).unwrap();
    let south = f.normal(std::f32::consts::PI, 2.0).unwrap();
    assert!(north.dot(Vec3::Z) > 1.0 - 1e-5 && south.dot(-Vec3::Z) > 1.0 - 1e-5);
}

#[test]
fn heart_normals_exist_and_point_inwards() {
    let f = ParamFunction::Heart;
    let centre = Vec3::ZERO;
    let mut inwards = 0;
    let points = grid(&f.domain(), 25);
    for &(u, v) in &points {
        let n = f
            .normal(u, v)
            .unwrap_or_else(|| panic!("no normal at ({u}, {v})"));
        assert!((n.length() - 1.0).abs() < 1e-5);
        inwards += usize::from(n.dot(f.position(u, v) - centre) < 0.0);
    }
    // The heart is star-shaped about its centre except near its dent, so nearly all agree.
    assert!(
        inwards * 10 > points.len() * 9,
        "{inwards} of {}",
        points.len()
    );
}

#[test]
fn normal_rejects_non_finite_and_degenerate_input() {
    let domain = ParamDomain::new([0.0, 1.0], [0.0, 1.0]).unwrap();
    assert!(surface_normal(sphere, &domain, f32::NAN, 0.5).is_none());
    assert!(surface_normal(|_, _| Vec3::ONE, &domain, 0.5, 0.5).is_none());
    assert!(surface_normal(|u, _| Vec3::new(u, 0.0, 0.0), &domain, 0.5, 0.5).is_none());
    // A plane: exact normal everywhere, edges and corners included.
    let plane = |u: f32, v: f32| Vec3::new(u, v, 0.0);
    for (u, v) in grid(&domain, 5) {
        assert_eq!(surface_normal(plane, &domain, u, v), Some(Vec3::Z));
    }
}

#[test]
fn domain_validation() {
    assert!(ParamDomain::new([0.0, 1.0], [1.0, 1.0]).is_err());
    assert!(ParamDomain::new([f32::NAN, 1.0], [0.0, 1.0]).is_err());
    assert!(ParamDomain::new([2.0, 1.0], [0.0, 1.0]).is_err());
    let d = ParamDomain::new([0.0, 2.0], [1.0, 4.0]).unwrap();
    assert_eq!(d.area(), 6.0);
}
