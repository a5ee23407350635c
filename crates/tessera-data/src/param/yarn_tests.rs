//! Tests of `yarn`.
use super::*;
use crate::param::functions::ParamFunction;

fn tubes() -> Vec<YarnTube> {
    let knit = KnitParams::default();
    let mut out = vec![YarnTube::new(knit, KnitCurve::Yarn, 0.5).unwrap()];
    out.extend(YarnTube::fibers(knit, 4, 0.15).unwrap());
    out
}

#[test]
fn yarn_curve_matches_crane() {
    let k = KnitParams::default();
    let t = 0.7_f64;
    let expected = DVec3::new(t + 1.5 * (2.0 * t).sin(), 4.0 * t.cos(), (2.0 * t).cos());
    assert!((k.yarn_curve(t) - expected).length() < 1e-15);
    assert_eq!(k.row_offset(), 4.5);
    // The curve repeats every 2π, shifted by 2π along x (one loop).
    let shifted = k.yarn_curve(t + TAU) - DVec3::new(TAU, 0.0, 0.0);
    assert!((shifted - k.yarn_curve(t)).length() < 1e-12);
}

#[test]
fn frenet_frame_is_orthonormal_and_follows_the_curve() {
    let k = KnitParams::default();
    for i in 0..50 {
        let t = i as f64 * 0.37;
        let [e1, e2, e3] = k.frenet_frame(t);
        for (a, b) in [(e1, e2), (e2, e3), (e1, e3)] {
            assert!(a.dot(b).abs() < 1e-12);
        }
        assert!((e1.length() - 1.0).abs() < 1e-12 && (e2.length() - 1.0).abs() < 1e-12);
        let h = 1e-6;
        let numeric = (k.yarn_curve(t + h) - k.yarn_curve(t - h)).normalize();
        assert!(numeric.dot(e1) > 1.0 - 1e-9);
        // The normal points towards the side the tangent turns to.
        let turn = k.frenet_frame(t + 1e-4)[0] - k.frenet_frame(t - 1e-4)[0];
        assert!(turn.dot(e2) > 0.0);
    }
}

#[test]
fn fibres_lie_at_the_yarn_radius() {
    let k = KnitParams::default();
    for i in 0..40 {
        let t = i as f64 * 0.29;
        let offset = k.fiber_curve(t, 0.8) - k.yarn_curve(t);
        assert!((offset.length() - k.yarn_radius).abs() < 1e-12);
        assert!(offset.dot(k.frenet_frame(t)[0]).abs() < 1e-12);
    }
}

#[test]
fn tube_points_lie_at_the_tube_radius() {
    for tube in tubes() {
        let d = tube.domain();
        for i in 0..=60 {
            let u = d.u[0] + (d.u[1] - d.u[0]) * i as f32 / 60.0;
            let t = f64::from(u);
            for j in 0..12 {
                let v = j as f32 * 0.5;
                let offset = tube.position(u, v).as_dvec3() - tube.centre(t);
                let r = tube.tube_radius();
                // f32 output of coordinates up to ~25 in size: a few 1e-6 of rounding.
                assert!(
                    (offset.length() - r).abs() < 1e-5,
                    "{:?} u={u} v={v}",
                    tube.curve()
                );
                assert!(offset.dot(tube.tangent(t)).abs() < 1e-5);
            }
        }
    }
}

#[test]
fn tubes_are_finite_and_continuous() {
    for tube in tubes() {
        let f = ParamFunction::Yarn(tube);
        let d = f.domain();
        let (nu, nv) = (2000, 32);
        let at = |i: usize, j: usize| {
            let u = d.u[0] + (d.u[1] - d.u[0]) * i as f32 / nu as f32;
            let v = d.v[0] + (d.v[1] - d.v[0]) * j as f32 / nv as f32;
            f.position(u, v)
        };
        for i in 0..nu {
            for j in 0..nv {
                let p = at(i, j);
                assert!(p.is_finite());
                // Steps of 8π/2000 along a curve of speed ≲ 10 and 2π/32 around a thin tube.
                assert!(
                    (at(i + 1, j) - p).length() < 0.15,
                    "{:?} ({i}, {j})",
                    tube.curve()
                );
                assert!((at(i, j + 1) - p).length() < 0.1);
            }
        }
        assert!(f.normal(1.0, 1.0).is_some());
    }
}

#[test]
fn tube_normals_point_away_from_the_curve() {
    let tube = YarnTube::new(KnitParams::default(), KnitCurve::Yarn, 0.5).unwrap();
    let f = ParamFunction::Yarn(tube);
    let (mut outward, mut inward) = (0, 0);
    for i in 0..40 {
        let u = 0.3 + i as f32 * 0.6;
        for j in 0..8 {
            let v = j as f32 * 0.78;
            let n = f.normal(u, v).unwrap();
            let spoke = (f.position(u, v).as_dvec3() - tube.centre(f64::from(u))).normalize();
            let c = f64::from(n.x) * spoke.x + f64::from(n.y) * spoke.y + f64::from(n.z) * spoke.z;
            assert!(c.abs() > 0.99, "u={u} v={v} cos={c}");
            if c > 0.0 {
                outward += 1;
            } else {
                inward += 1;
            }
        }
    }
    // One consistent orientation over the whole tube.
    assert!(outward == 0 || inward == 0, "{outward} {inward}");
}

#[test]
fn invalid_tubes_are_rejected() {
    let k = KnitParams::default();
    assert!(YarnTube::new(k, KnitCurve::Yarn, 0.0).is_err());
    assert!(YarnTube::new(k, KnitCurve::Fiber { phase: f64::NAN }, 0.1).is_err());
    assert!(YarnTube::new(KnitParams { loops: 0, ..k }, KnitCurve::Yarn, 0.1).is_err());
    assert!(YarnTube::new(
        KnitParams {
            height: f64::INFINITY,
            ..k
        },
        KnitCurve::Yarn,
        0.1
    )
    .is_err());
    assert!(YarnTube::fibers(k, 0, 0.1).is_err());
}
