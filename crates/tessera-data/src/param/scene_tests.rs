//! Tests of `scene`: the CPU bounds hold for the CPU's own surfaces. The GPU side of the same
//! claim (shader positions inside these bounds) is `tessera/tests/param_shapes.rs`.

use super::*;
use crate::param::functions::tests::grid;
use crate::param::sh::sh_coefficient_count;
use crate::param::{KnitParams, ParamDomain, ShBasis, ShGlyph};
use glam::Quat;

fn shells() -> Vec<SeashellParams> {
    // A spiral that shrinks (α > 90°, largest radius at θ = 0) with sunken nodules, too.
    let shrinking = SeashellParams {
        alpha_deg: 93.0,
        turns: 3.0,
        nodule_height_along: -8.0,
        ..SeashellParams::default()
    };
    vec![
        SeashellParams::default(),
        SeashellParams::ridged(),
        SeashellParams::fine_bumps(),
        shrinking,
    ]
}

fn tubes() -> Vec<YarnTube> {
    let knit = KnitParams::default();
    let wide = KnitParams {
        roundness: -2.0,
        height: 3.0,
        depth: 2.5,
        ..knit
    };
    let mut out = vec![YarnTube::new(knit, KnitCurve::Yarn, 0.8).unwrap()];
    out.extend(YarnTube::fibers(knit, 6, 0.3).unwrap());
    out.push(YarnTube::new(wide, KnitCurve::Fiber { phase: 1.0 }, 0.4).unwrap());
    out
}

/// Every CPU position lies in the object bound, and the bound is not loose: some position
/// comes within 80 % of it (so a bound of, say, twice the size would fail). The unit sphere's
/// f32 positions stray an ulp past 1, which the 1e-6 allows.
#[test]
fn bounds_hold_and_are_tight() {
    let functions: Vec<ParamFunction> = (shells().into_iter().map(ParamFunction::Seashell))
        .chain(tubes().into_iter().map(ParamFunction::Yarn))
        .chain([ParamFunction::Sphere, ParamFunction::Heart])
        .collect();
    for f in functions {
        let object = ParamObject::new(f);
        let bound = object.object_radius();
        let reach = grid(&object.function.domain(), 301)
            .into_iter()
            .map(|(u, v)| object.function.position(u, v).length())
            .fold(0.0f32, f32::max);
        assert!(
            reach <= bound * (1.0 + 1e-6),
            "{:?}: {reach} > {bound}",
            object.function
        );
        assert!(
            reach > 0.8 * bound,
            "{:?}: {reach} of {bound}",
            object.function
        );
    }
}

/// Raw SH glyphs are bounded by their coefficients; normalised ones by 1; user functions are
/// unknown until measured.
#[test]
fn glyph_and_user_bounds() {
    let mut c = vec![0.0; sh_coefficient_count(4).unwrap()];
    c[0] = 2.0;
    c[3] = -0.5;
    let basis = ShBasis::Descoteaux07 { legacy: false };
    let raw = ShGlyph::new(basis, 4, c.clone(), RadiusNormalization::Raw).unwrap();
    let object = ParamObject::new(ParamFunction::ShGlyph(raw));
    let bound = object.object_radius();
    for (u, v) in grid(&object.function.domain(), 61) {
        assert!(object.function.position(u, v).length() <= bound);
    }
    let minmax = ShGlyph::new(basis, 4, c, RadiusNormalization::MinMax).unwrap();
    assert_eq!(
        ParamObject::new(ParamFunction::ShGlyph(minmax)).object_radius(),
        1.0
    );
    let domain = ParamDomain::new([0.0, 1.0], [0.0, 1.0]).unwrap();
    let user = ParamObject::new(ParamFunction::User(domain));
    assert_eq!(user.object_radius(), f32::INFINITY);
}

/// The world sphere follows the transform: centred on the translation, grown by the scale,
/// and holding the transformed surface.
#[test]
fn bounding_sphere_follows_the_transform() {
    let place = Mat4::from_scale_rotation_translation(
        Vec3::new(0.5, 2.0, 1.0),
        Quat::from_rotation_y(0.7),
        Vec3::new(1.0, -2.0, 3.0),
    );
    let object = ParamObject::new(ParamFunction::Heart)
        .with_transform(place)
        .with_colour([0.1, 0.2, 0.3]);
    let (centre, radius) = object.bounding_sphere();
    assert_eq!(centre, Vec3::new(1.0, -2.0, 3.0));
    assert!(radius >= 2.0, "{radius}");
    for (u, v) in grid(&object.function.domain(), 41) {
        let p = place.transform_point3(object.function.position(u, v));
        assert!(p.distance(centre) <= radius * (1.0 + 1e-6));
    }
    let scene = ParamScene::new(vec![
        object.clone(),
        ParamObject::new(ParamFunction::Sphere),
    ]);
    assert_eq!(scene.bounding_spheres()[0], (centre, radius));
    let refs = scene.reference_objects();
    assert_eq!(refs[0].object_to_world, place);
    assert_eq!(refs[0].colour, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(refs[1].colour, Vec3::splat(0.85));
}

/// A glyph with a negative lobe: min-max lifts it, abs draws |r| / max|r|, and renormalizing a
/// raw glyph samples the range it lacked.
#[test]
fn glyph_radius_mappings() {
    let basis = ShBasis::Descoteaux07 { legacy: false };
    let mut c = vec![0.0; sh_coefficient_count(2).unwrap()];
    c[0] = 0.1;
    c[3] = 1.0; // (l, m) = (2, 0): negative around the equator
    let raw = ShGlyph::new(basis, 2, c, RadiusNormalization::Raw).unwrap();
    let scene = ParamScene::new(vec![ParamObject::new(ParamFunction::ShGlyph(raw.clone()))]);
    let abs = scene.with_glyph_radius(RadiusNormalization::MaxAbs);
    let ParamFunction::ShGlyph(g) = &abs.objects[0].function else {
        panic!("not a glyph")
    };
    let (lo, hi) = g.raw_range();
    assert!(lo < 0.0 && hi > 0.0, "range {lo} {hi}");
    let m = lo.abs().max(hi);
    let function = &abs.objects[0].function;
    for (u, v) in grid(&function.domain(), 17) {
        let r = raw.raw_radius(f64::from(u), f64::from(v));
        let length = f64::from(function.position(u, v).length());
        assert!((length - r.abs() / m).abs() < 1e-5, "at ({u}, {v})");
    }
    let minmax = raw.renormalized(RadiusNormalization::MinMax);
    let equator = std::f64::consts::FRAC_PI_2;
    assert!(raw.raw_radius(equator, 0.0) < 0.0);
    assert!((minmax.radius(equator, 0.0) - 0.0).abs() < 1e-3);
    assert!((minmax.radius(0.0, 0.0) - 1.0).abs() < 1e-9);
    let positive = raw.renormalized(RadiusNormalization::PositiveLobes);
    assert_eq!(positive.radius(equator, 0.0), 0.0);
    assert!((positive.radius(0.0, 0.0) - 1.0).abs() < 1e-9);
    let polar = 0.3;
    let expected = raw.raw_radius(polar, 0.0) / positive.raw_range().1;
    assert!((positive.radius(polar, 0.0) - expected).abs() < 1e-12);
}
