//! Tests of `lod`.
use super::*;
use crate::param::functions::{sphere, ParamFunction};
use crate::param::glyph::{RadiusNormalization, ShGlyph};
use crate::param::sh::ShBasis;

const SIZE: Vec2 = Vec2::new(512.0, 512.0);

/// Pinhole camera looking from `eye` at `target`, 60° vertical field of view, pixels y-down.
struct Camera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    focal: f32,
}

impl Camera {
    fn look_at(eye: Vec3, target: Vec3) -> Camera {
        let forward = (target - eye).normalize();
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        let focal = SIZE.y * 0.5 / 30.0_f32.to_radians().tan();
        Camera {
            eye,
            forward,
            right,
            up,
            focal,
        }
    }

    fn project(&self, p: Vec3) -> Option<Vec2> {
        let d = p - self.eye;
        let z = d.dot(self.forward);
        (z > 1e-4).then(|| {
            Vec2::new(
                SIZE.x * 0.5 + self.focal * d.dot(self.right) / z,
                SIZE.y * 0.5 - self.focal * d.dot(self.up) / z,
            )
        })
    }
}

fn sphere_patch() -> Patch {
    Patch::from_domain(&ParamFunction::Sphere.domain(), 0)
}

fn sphere_surface(_: u32, u: f32, v: f32) -> Vec3 {
    sphere(u, v)
}

fn run_sphere(eye: Vec3, target: Vec3, config: &LodConfig) -> LodOutput {
    let cam = Camera::look_at(eye, target);
    run_lod(
        &[sphere_patch()],
        sphere_surface,
        |p| cam.project(p),
        config,
    )
    .unwrap()
}

/// Asserts that no two output patches overlap in their interiors.
fn assert_disjoint(render: &[RenderPatch]) {
    let overlap = |a: [f32; 2], b: [f32; 2]| a[0].max(b[0]) < a[1].min(b[1]);
    for (i, a) in render.iter().enumerate() {
        for b in &render[i + 1..] {
            assert!(
                !(a.patch.object == b.patch.object
                    && overlap(a.patch.u, b.patch.u)
                    && overlap(a.patch.v, b.patch.v)),
                "{:?} overlaps {:?}",
                a.patch,
                b.patch
            );
        }
    }
}

fn area(render: &[RenderPatch]) -> f64 {
    render.iter().map(|r| r.patch.area()).sum()
}

#[test]
fn far_sphere_stays_one_patch() {
    let out = run_sphere(
        Vec3::new(0.0, 0.0, -100.0),
        Vec3::ZERO,
        &LodConfig::new(SIZE),
    );
    assert_eq!(out.render.len(), 1);
    assert_eq!(out.render[0].patch, sphere_patch());
    assert_eq!(out.render[0].step, 0);
    assert!(!out.render[0].over_threshold);
    assert_eq!(out.culled, 0);
    let mut expected = vec![0; DEFAULT_MAX_STEPS as usize];
    expected[0] = 1;
    assert_eq!(out.evaluated_per_step, expected);
}

#[test]
fn close_sphere_splits_until_every_patch_is_within_thresholds() {
    let mut config = LodConfig::new(SIZE);
    config.thresholds = Vec2::new(32.0, 24.0);
    let cam = Camera::look_at(Vec3::new(0.3, 0.4, -3.0), Vec3::ZERO);
    let out = run_lod(
        &[sphere_patch()],
        sphere_surface,
        |p| cam.project(p),
        &config,
    )
    .unwrap();
    assert!(out.render.len() > 50, "{}", out.render.len());
    assert!(!out.hit_iteration_limit());
    assert_eq!((out.culled, out.resolution_hits), (0, 0));
    for r in &out.render {
        assert!(!r.over_threshold);
        let eval = evaluate_patch(&r.patch, &sphere_surface, &|p| cam.project(p), &config);
        assert_eq!(eval.max_extent(), r.extent);
        assert!(
            r.extent.x <= config.thresholds.x && r.extent.y <= config.thresholds.y,
            "{r:?}"
        );
    }
    // Nothing culled: the output tiles the domain exactly (midpoint splits are exact in f64).
    assert_eq!(area(&out.render), sphere_patch().area());
    assert_disjoint(&out.render);
    // Non-uniform subdivision: patches of several sizes come out of several steps.
    let steps: std::collections::BTreeSet<u32> = out.render.iter().map(|r| r.step).collect();
    assert!(steps.len() >= 2, "{steps:?}");
}

#[test]
fn iteration_limit_is_reported_and_still_tiles() {
    let mut config = LodConfig::new(SIZE);
    config.thresholds = Vec2::splat(16.0);
    config.max_steps = 2;
    let out = run_sphere(Vec3::new(0.0, 0.0, -2.5), Vec3::ZERO, &config);
    assert!(out.hit_iteration_limit());
    let forced = out.render.iter().filter(|r| r.over_threshold).count();
    assert_eq!(forced, out.limit_hits);
    assert!(out
        .render
        .iter()
        .filter(|r| r.over_threshold)
        .all(|r| r.step == 1));
    assert_eq!(area(&out.render), sphere_patch().area());
    assert_disjoint(&out.render);
}

#[test]
fn off_screen_and_behind_patches_are_culled() {
    let config = LodConfig::new(SIZE);
    // Far to the right of the view.
    let out = run_sphere(
        Vec3::new(-60.0, 0.0, -10.0),
        Vec3::new(-60.0, 0.0, 0.0),
        &config,
    );
    assert_eq!((out.culled, out.render.len()), (1, 0));
    // Behind the camera.
    let out = run_sphere(
        Vec3::new(0.0, 0.0, -10.0),
        Vec3::new(0.0, 0.0, -20.0),
        &config,
    );
    assert_eq!((out.culled, out.render.len()), (1, 0));
    // Without culling the same patch is kept.
    let off = LodConfig {
        frustum_culling: false,
        ..config
    };
    let out = run_sphere(Vec3::new(0.0, 0.0, -10.0), Vec3::new(0.0, 0.0, -20.0), &off);
    assert_eq!((out.culled, out.render.len()), (0, 1));
}

#[test]
fn partly_visible_sphere_culls_only_hidden_parts() {
    let mut config = LodConfig::new(SIZE);
    config.thresholds = Vec2::splat(48.0);
    let (eye, target) = (Vec3::new(0.0, 0.0, -2.2), Vec3::new(1.5, 0.0, 0.0));
    let culled = run_sphere(eye, target, &config);
    assert!(culled.culled > 0 && !culled.render.is_empty());
    assert!(area(&culled.render) < sphere_patch().area());
    assert_disjoint(&culled.render);
    let kept = run_sphere(
        eye,
        target,
        &LodConfig {
            frustum_culling: false,
            ..config
        },
    );
    assert_eq!(kept.culled, 0);
    assert_eq!(area(&kept.render), sphere_patch().area());
    // Off-screen geometry asks for no detail (clamped extents), so culling does not change the
    // patches that survive.
    assert!(culled.render.iter().all(|r| kept.render.contains(r)));
}

#[test]
fn results_are_deterministic() {
    let mut config = LodConfig::new(SIZE);
    config.thresholds = Vec2::splat(40.0);
    let a = run_sphere(Vec3::new(0.5, 1.0, -3.0), Vec3::ZERO, &config);
    let b = run_sphere(Vec3::new(0.5, 1.0, -3.0), Vec3::ZERO, &config);
    assert_eq!(a, b);
}

/// Orthographic view of the plane `(u, v, 0)`, 100 px per unit, origin at pixel (256, 256).
fn plane_surface(_: u32, u: f32, v: f32) -> Vec3 {
    Vec3::new(u, v, 0.0)
}

fn ortho(p: Vec3) -> Option<Vec2> {
    Some(Vec2::new(256.0 + 100.0 * p.x, 256.0 + 100.0 * p.y))
}

#[test]
fn extents_sum_clamped_segments() {
    let config = LodConfig::new(SIZE);
    let eval = evaluate_patch(
        &Patch::new([0.0, 1.0], [0.0, 1.0], 0),
        &plane_surface,
        &ortho,
        &config,
    );
    for e in eval.extents_u.iter().chain(&eval.extents_v) {
        assert!((e - 100.0).abs() < 1e-3, "{e}");
    }
    assert_eq!(eval.pattern, SplitPattern::Quarter);
    // Half of this patch lies left of the screen: it is clamped to x = 0 and measures nothing.
    let eval = evaluate_patch(
        &Patch::new([-4.0, -2.44], [0.0, 1.0], 0),
        &plane_surface,
        &ortho,
        &config,
    );
    assert!(
        eval.extents_u.iter().all(|e| (e - 12.0).abs() < 1e-3),
        "{:?}",
        eval.extents_u
    );
    // Samples behind the camera contribute no length.
    let hide_right = |p: Vec3| (p.x <= 0.5).then(|| ortho(p).unwrap());
    let eval = evaluate_patch(
        &Patch::new([0.0, 0.7], [0.0, 1.0], 0),
        &plane_surface,
        &hide_right,
        &config,
    );
    assert!(
        eval.extents_u.iter().all(|e| (e - 50.0).abs() < 1e-3),
        "{:?}",
        eval.extents_u
    );
    assert_eq!(eval.outcode_and, 0);
}

#[test]
fn plane_quarters_then_stops() {
    let config = LodConfig::new(SIZE);
    let out = run_lod(
        &[Patch::new([0.0, 1.0], [0.0, 1.0], 7)],
        plane_surface,
        ortho,
        &config,
    )
    .unwrap();
    assert_eq!(out.render.len(), 4);
    let expected = SplitPattern::Quarter.children(&Patch::new([0.0, 1.0], [0.0, 1.0], 7));
    for (r, e) in out.render.iter().zip(&expected) {
        assert_eq!((r.patch, r.step, r.over_threshold), (*e, 1, false));
        assert!((r.extent - Vec2::splat(50.0)).abs().max_element() < 1e-3);
    }
}

#[test]
fn sample_layout_matches_the_documented_formulas() {
    let p = Patch::new([1.0, 3.0], [-2.0, 2.0], 0);
    let s = sample_params(&p);
    for k in 0..4 {
        let across = k as f32 + 0.5;
        assert_eq!(s.u_lines[k][0], Vec2::new(1.0, -2.0 + 1.0 * across));
        assert_eq!(s.u_lines[k][7].y, s.u_lines[k][0].y);
        assert!((s.u_lines[k][7].x - 3.0).abs() < 1e-6);
        assert_eq!(s.v_lines[k][0], Vec2::new(1.0 + 0.5 * across, -2.0));
        assert!((s.v_lines[k][7].y - 2.0).abs() < 1e-6);
    }
    assert_eq!(s.grid[0], Vec2::new(1.0, -2.0));
    assert_eq!(s.grid[4], Vec2::new(3.0, -2.0));
    assert_eq!(s.grid[12], Vec2::new(2.0, 0.0));
    assert_eq!(s.grid[24], Vec2::new(3.0, 2.0));
}

#[test]
fn unsplittable_ranges_are_reported_not_looped() {
    let u0 = 1.0_f32;
    let u1 = f32::from_bits(u0.to_bits() + 1);
    let huge = |p: Vec3| Some(Vec2::new(1e9 * (p.x - 1.0), 1e9 * (p.y - 1.0)));
    let config = LodConfig {
        frustum_culling: false,
        ..LodConfig::new(SIZE)
    };
    let out = run_lod(
        &[Patch::new([u0, u1], [1.0, 1.5], 0)],
        plane_surface,
        huge,
        &config,
    )
    .unwrap();
    assert!(out.resolution_hits > 0);
    assert!(out.render.iter().all(|r| r.patch.u == [u0, u1]));
    assert_eq!(
        area(&out.render),
        Patch::new([u0, u1], [1.0, 1.5], 0).area()
    );
}

#[test]
fn bad_input_is_an_error() {
    let ok = sphere_patch();
    let cam = |p: Vec3| Some(p.truncate());
    let config = LodConfig::new(SIZE);
    for bad in [
        Patch::new([1.0, 0.0], [0.0, 1.0], 0),
        Patch::new([0.0, 1.0], [0.5, 0.5], 0),
        Patch::new([f32::NAN, 1.0], [0.0, 1.0], 0),
        Patch::new([-f32::MAX, f32::MAX], [0.0, 1.0], 0),
    ] {
        assert!(
            run_lod(&[ok, bad], sphere_surface, cam, &config).is_err(),
            "{bad:?}"
        );
    }
    for bad in [
        LodConfig {
            max_steps: 0,
            ..config
        },
        LodConfig {
            max_steps: MAX_STEPS_LIMIT + 1,
            ..config
        },
        LodConfig {
            thresholds: Vec2::new(0.0, 5.0),
            ..config
        },
        LodConfig {
            viewport: Vec2::new(f32::NAN, 5.0),
            ..config
        },
        LodConfig {
            max_patches: 0,
            ..config
        },
    ] {
        assert!(
            run_lod(&[ok], sphere_surface, cam, &bad).is_err(),
            "{bad:?}"
        );
    }
    // Running out of patch budget is an error, not an unbounded allocation.
    let tight = LodConfig {
        max_patches: 3,
        thresholds: Vec2::splat(8.0),
        ..config
    };
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO);
    assert!(run_lod(&[ok], sphere_surface, |p| cam.project(p), &tight).is_err());
    // No patches is fine.
    assert_eq!(
        run_lod(&[], sphere_surface, |p| cam.project(p), &config)
            .unwrap()
            .render
            .len(),
        0
    );
}

#[test]
fn sh_glyph_close_up_subdivides_and_tiles() {
    let mut coeffs = vec![0.0; 45];
    coeffs[0] = 1.0;
    coeffs[3] = 0.8;
    coeffs[12] = 0.3;
    coeffs[30] = -0.2;
    let glyph = ShGlyph::new(
        ShBasis::Tournier07 { legacy: false },
        8,
        coeffs,
        RadiusNormalization::MinMax,
    )
    .unwrap();
    let objects = [ParamFunction::ShGlyph(glyph), ParamFunction::Sphere];
    let patches: Vec<Patch> = objects
        .iter()
        .enumerate()
        .map(|(i, f)| Patch::from_domain(&f.domain(), i as u32))
        .collect();
    let cam = Camera::look_at(Vec3::new(0.2, 0.3, -2.5), Vec3::ZERO);
    let surface = |o: u32, u: f32, v: f32| {
        let p = objects[o as usize].position(u, v);
        if o == 1 {
            p * 0.5 + Vec3::new(0.0, 0.0, 3.0)
        } else {
            p
        }
    };
    let mut config = LodConfig::new(SIZE);
    config.thresholds = Vec2::splat(64.0);
    let out = run_lod(&patches, surface, |p| cam.project(p), &config).unwrap();
    assert!(!out.hit_iteration_limit());
    assert_eq!(out.culled, 0);
    for (i, p) in patches.iter().enumerate() {
        let mine: Vec<RenderPatch> = out
            .render
            .iter()
            .filter(|r| r.patch.object == i as u32)
            .copied()
            .collect();
        assert!(mine.len() > 1, "object {i}");
        assert_eq!(area(&mine), p.area());
    }
    assert_disjoint(&out.render);
    assert!(out.render.iter().all(|r| r.extent.max_element() <= 64.0));
}
