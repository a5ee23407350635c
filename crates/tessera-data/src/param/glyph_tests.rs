//! Tests of `glyph`.
use super::*;
use crate::param::functions::{ParamDomain, ParamFunction};
use crate::param::sh::sh_coefficient_count;

const BASIS: ShBasis = ShBasis::Descoteaux07 { legacy: true };

fn test_grid(n: usize) -> Vec<(f32, f32)> {
    let d = ParamDomain::new([0.0, std::f32::consts::PI], [0.0, std::f32::consts::TAU]).unwrap();
    crate::param::functions::tests::grid(&d, n)
}

/// A lobed order-8 glyph with a dominant l = 0 term.
fn lobed() -> Vec<f64> {
    let mut c = vec![0.0; sh_coefficient_count(8).unwrap()];
    c[0] = 2.0;
    c[3] = 0.6; // l = 2, m = 0: elongated along z
    c[14] = -0.3; // l = 4, m = 4
    c[40] = 0.2; // l = 8
    c
}

#[test]
fn l0_only_is_a_sphere() {
    let mut c = vec![0.0; 45];
    c[0] = 3.0;
    let expected_r = 3.0 / (2.0 * PI.sqrt());
    let raw = ShGlyph::new(BASIS, 8, c.clone(), RadiusNormalization::Raw).unwrap();
    let minmax = ShGlyph::new(BASIS, 8, c.clone(), RadiusNormalization::MinMax).unwrap();
    let maxabs = ShGlyph::new(BASIS, 8, c, RadiusNormalization::MaxAbs).unwrap();
    for (u, v) in test_grid(21) {
        let s = crate::param::functions::sphere(u, v);
        assert!((raw.position(u, v) - s * expected_r as f32).length() < 1e-6);
        assert!((minmax.position(u, v) - s).length() < 1e-6);
        assert!((maxabs.position(u, v) - s).length() < 1e-6);
    }
}

#[test]
fn minmax_maps_the_range_to_unit_interval() {
    let g = ShGlyph::new(BASIS, 8, lobed(), RadiusNormalization::MinMax).unwrap();
    let (lo, hi) = g.raw_range();
    assert!(lo < hi);
    let mut seen_lo = f64::INFINITY;
    let mut seen_hi = f64::NEG_INFINITY;
    for (u, v) in test_grid(61) {
        let r = g.radius(f64::from(u), f64::from(v));
        assert!((0.0..=1.0).contains(&r));
        let expected =
            ((g.raw_radius(f64::from(u), f64::from(v)) - lo) / (hi - lo)).clamp(0.0, 1.0);
        assert!((r - expected).abs() < 1e-12);
        seen_lo = seen_lo.min(r);
        seen_hi = seen_hi.max(r);
    }
    // The grid of `new` is finer than this one, so this one sees nearly the full range.
    assert!(seen_lo < 0.02 && seen_hi > 0.98, "{seen_lo} {seen_hi}");
    // The raw glyph is elongated along z (positive l = 2, m = 0 term).
    let raw = ShGlyph::new(BASIS, 8, lobed(), RadiusNormalization::Raw).unwrap();
    assert!(raw.raw_radius(0.0, 0.0) > raw.raw_radius(std::f64::consts::FRAC_PI_2, 0.3));
    assert_eq!(raw.raw_range(), (0.0, 0.0));
}

#[test]
fn maxabs_scales_by_the_largest_magnitude() {
    let g = ShGlyph::new(BASIS, 8, lobed(), RadiusNormalization::MaxAbs).unwrap();
    let (lo, hi) = g.raw_range();
    let m = lo.abs().max(hi.abs());
    let r = g.radius(0.4, 1.0);
    assert!((r - g.raw_radius(0.4, 1.0) / m).abs() < 1e-12);
    let zero = ShGlyph::new(BASIS, 2, vec![0.0; 6], RadiusNormalization::MaxAbs).unwrap();
    assert_eq!(zero.position(1.0, 1.0), Vec3::ZERO);
}

#[test]
fn raw_negative_radius_flips_through_the_centre() {
    // Pure l = 2, m = 0 is negative around the equator.
    let mut c = vec![0.0; 6];
    c[3] = 1.0;
    let g = ShGlyph::new(BASIS, 2, c, RadiusNormalization::Raw).unwrap();
    let p = g.position(std::f32::consts::FRAC_PI_2, 0.0);
    assert!(p.x < 0.0, "{p}");
}

#[test]
fn invalid_glyphs_are_errors() {
    assert!(ShGlyph::new(BASIS, 3, vec![0.0; 10], RadiusNormalization::Raw).is_err());
    assert!(ShGlyph::new(BASIS, 4, vec![0.0; 14], RadiusNormalization::Raw).is_err());
    let mut c = vec![0.0; 15];
    c[2] = f64::INFINITY;
    assert!(ShGlyph::new(BASIS, 4, c, RadiusNormalization::MinMax).is_err());
}

#[test]
fn glyph_normals_are_finite_at_the_poles() {
    let f =
        ParamFunction::ShGlyph(ShGlyph::new(BASIS, 8, lobed(), RadiusNormalization::Raw).unwrap());
    for (u, v) in test_grid(17) {
        let n = f
            .normal(u, v)
            .unwrap_or_else(|| panic!("no normal at ({u}, {v})"));
        assert!((n.length() - 1.0).abs() < 1e-5);
        // The lobed glyph stays star-shaped, so the normal faces away from the centre.
        assert!(n.dot(f.position(u, v)) > 0.0, "({u}, {v})");
    }
    // At the poles the glyph is symmetric enough (only m = 0 and m = 4 terms) for ±z.
    assert!(f.normal(0.0, 1.0).unwrap().z > 0.999);
    assert!(f.normal(std::f32::consts::PI, 1.0).unwrap().z < -0.999);
}

#[test]
fn colour_is_absolute_direction() {
    assert_eq!(direction_colour(Vec3::new(0.0, -2.0, 0.0)), Vec3::Y);
    let c = direction_colour(Vec3::new(-1.0, 1.0, 0.0));
    assert!((c - Vec3::new(1.0, 1.0, 0.0) / 2.0_f32.sqrt()).length() < 1e-6);
    assert_eq!(direction_colour(Vec3::ZERO), Vec3::splat(0.5));
    // Antipodal points of a glyph share a colour.
    assert_eq!(
        direction_colour(Vec3::new(0.3, -0.4, 0.5)),
        direction_colour(Vec3::new(-0.3, 0.4, -0.5))
    );
}
