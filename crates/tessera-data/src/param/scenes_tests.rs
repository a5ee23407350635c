//! Tests of `scenes`: the curtain's layout and the seashell's placement, on the CPU.

use super::*;
use crate::param::reference::world_position;

/// The curtain's knit with a twist that is no whole number, so that fibres do not repeat with
/// the loop.
fn odd_twist() -> KnitParams {
    KnitParams {
        twist: 4.3,
        ..curtain_knit()
    }
}

/// Loops meet loops: the end of every loop is the start of the next one in the row, for yarns
/// and for fibres (whose phases must continue, visible only with a twist that is no whole
/// number); rows lie `row_offset` apart; the curtain is centred with its longer side 1.
#[test]
fn curtain_is_one_continuous_fabric() {
    let tau = std::f32::consts::TAU;
    for (knit, fibres) in [(curtain_knit(), false), (odd_twist(), true)] {
        let (rows, loops) = (3, 4);
        let scene = yarn_curtain_of(knit, rows, loops, fibres).unwrap();
        let per = if fibres { CURTAIN_FIBRES } else { 1 };
        assert_eq!(scene.objects.len(), (rows * loops * per) as usize);
        let objects = scene.reference_objects();
        let at = |row: u32, k: u32, f: u32, u: f32, v: f32| {
            world_position(&objects[((row * loops + k) * per + f) as usize], u, v)
        };
        let scale = 1.0 / (tau * loops as f32);
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for row in 0..rows {
            for k in 0..loops {
                for f in 0..per {
                    for v in [0.0, 1.0, 2.5, 4.0] {
                        let start = at(row, k, f, 0.0, v);
                        for i in 0..32 {
                            let p = at(row, k, f, tau * i as f32 / 32.0, v);
                            lo = lo.min(p);
                            hi = hi.max(p);
                        }
                        if k + 1 < loops {
                            let gap = (at(row, k, f, tau, v) - at(row, k + 1, f, 0.0, v)).length();
                            assert!(gap < 1e-5, "row {row} loop {k} fibre {f} v {v}: gap {gap}");
                        }
                        if row > 0 {
                            let step = start - at(row - 1, k, f, 0.0, v);
                            let expected = Vec3::Y * (knit.row_offset() as f32 * scale);
                            assert!((step - expected).length() < 1e-5, "{step}");
                        }
                    }
                }
            }
        }
        // Crane's loops are symmetric about the middle of a row: the curtain's box is centred
        // on the origin in x and y (up to the sampling of u), its width 1.
        let middle = (lo + hi) * 0.5;
        assert!(middle.truncate().abs().max_element() < 0.01, "{middle}");
        assert!(((hi - lo).x - 1.0).abs() < 0.1, "{lo} {hi}");
    }
    assert_eq!(yarn_curtain(2, 3, true).unwrap().objects.len(), 36);
    // The paper's "60k yarn curves".
    assert_eq!(paper_curtain(false).unwrap().objects.len(), 59_690);
}

/// Empty curtains and curtains beyond the object limit are refused before anything is built.
#[test]
fn curtain_sizes_are_checked() {
    for (rows, loops, fibres) in [(0, 3, false), (2, 0, true), (4097, 4097, false)] {
        let err = yarn_curtain(rows, loops, fibres).unwrap_err().to_string();
        assert!(
            err.contains(&format!("{rows} rows of {loops} loops")) && err.contains("16777216"),
            "{err}"
        );
    }
}

/// The shell's object bound is scaled to 1 and every point lies within 1 of the placed centre;
/// an invalid shell is refused with the reason.
#[test]
fn seashell_fits_the_unit_sphere() {
    for params in [SeashellParams::default(), SeashellParams::fine_bumps()] {
        let scene = seashell(params).unwrap();
        assert_eq!(scene.objects.len(), 1);
        let object = &scene.objects[0];
        assert_eq!(object.colour, SHELL_COLOUR);
        let centre = object.object_to_world.w_axis.truncate();
        let radius = object.object_radius() * object.object_to_world.x_axis.length();
        assert!((radius - 1.0).abs() < 1e-5, "{radius}");
        // The world sphere's Frobenius stretch overestimates a uniform scale by √3.
        let (_, world) = object.bounding_sphere();
        assert!((world - 3f32.sqrt()).abs() < 1e-5, "{world}");
        let reference = object.reference();
        let d = params.domain();
        for i in 0..=64 {
            for j in 0..=16 {
                let u = d.u[0] + (d.u[1] - d.u[0]) * i as f32 / 64.0;
                let v = d.v[0] + (d.v[1] - d.v[0]) * j as f32 / 16.0;
                let p = world_position(&reference, u, v);
                assert!(p.distance(centre) <= radius * (1.0 + 1e-5), "{u} {v}: {p}");
            }
        }
    }
    let flat = SeashellParams {
        turns: 0.0,
        ..SeashellParams::default()
    };
    let err = seashell(flat).unwrap_err().to_string();
    assert!(err.starts_with("seashell: "), "{err}");
}
