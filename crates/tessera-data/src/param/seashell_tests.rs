//! Tests of `seashell`.
use super::*;
use crate::param::functions::ParamFunction;

fn variants() -> [SeashellParams; 3] {
    [
        SeashellParams::default(),
        SeashellParams::ridged(),
        SeashellParams::fine_bumps(),
    ]
}

/// Largest distance between consecutive samples along a line of `u` (`along_u`) or of `v`,
/// through the other parameter's value `at`, with `n` steps across the domain.
fn max_step(p: &SeashellParams, along_u: bool, at: f32, n: usize) -> f32 {
    let d = p.domain();
    let range = if along_u { d.u } else { d.v };
    let point = |i: usize| {
        let s = range[0] + (range[1] - range[0]) * i as f32 / n as f32;
        if along_u {
            p.position(s, at)
        } else {
            p.position(at, s)
        }
    };
    let mut prev = point(0);
    let mut step = 0.0_f32;
    for i in 1..=n {
        let here = point(i);
        assert!(here.is_finite(), "{i}");
        step = step.max((here - prev).length());
        prev = here;
    }
    step
}

#[test]
fn variants_are_valid_finite_and_continuous() {
    for p in variants() {
        p.validate().unwrap();
        let d = p.domain();
        // Halving the sample spacing roughly halves the largest step: no jumps. The spacing is
        // fine enough to resolve the smallest nodules (70 per turn along u, 50 around v).
        for v in [0.3, 2.0, 4.5] {
            let (coarse, fine) = (max_step(&p, true, v, 40_000), max_step(&p, true, v, 80_000));
            assert!(
                fine < 0.6 * coarse,
                "{p:?} along u at v = {v}: {coarse} {fine}"
            );
        }
        for u in [0.5 * d.u[1], d.u[1]] {
            let (coarse, fine) = (max_step(&p, false, u, 4_000), max_step(&p, false, u, 8_000));
            assert!(
                fine < 0.6 * coarse,
                "{p:?} along v at u = {u}: {coarse} {fine}"
            );
        }
        // The shell is a few units across (the authors place variants 4.5 units apart).
        let far = p.position(d.u[1], 0.0).length();
        assert!(far > 0.5 && far < 20.0, "{far}");
    }
}

#[test]
fn opening_closes_around_v_and_grows_along_u() {
    let p = SeashellParams::default();
    let tau = std::f32::consts::TAU;
    for u in [1.0, 20.0, 45.0] {
        assert!((p.position(u, 0.0) - p.position(u, tau)).length() < 1e-4);
    }
    // The opening's size at u is proportional to the spiral radius exp(u cot α).
    let size = |u: f32| (p.position(u, 0.0) - p.position(u, tau / 2.0)).length();
    assert!(size(40.0) > 3.0 * size(10.0));
}

#[test]
fn nodules_modulate_the_surface() {
    let smooth = SeashellParams {
        nodule_height_around: 0.0,
        ..SeashellParams::default()
    };
    let bumpy = SeashellParams::default();
    let (u, v) = (30.0, 1.0);
    assert!((bumpy.position(u, v) - smooth.position(u, v)).length() > 1e-3);
    assert!(ParamFunction::Seashell(bumpy).normal(u, v).is_some());
}

#[test]
fn invalid_parameters_are_rejected() {
    let bad = [
        SeashellParams {
            turns: 0.0,
            ..Default::default()
        },
        SeashellParams {
            alpha_deg: 180.0,
            ..Default::default()
        },
        SeashellParams {
            nodules_along: 0.0,
            ..Default::default()
        },
        SeashellParams {
            scale: f32::NAN,
            ..Default::default()
        },
        SeashellParams {
            nodule_width_around: -1.0,
            ..Default::default()
        },
    ];
    for p in bad {
        assert!(p.validate().is_err(), "{p:?}");
    }
}
