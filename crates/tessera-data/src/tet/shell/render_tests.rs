//! Tests of emission–absorption and shadow rays by shell traversal against the exact
//! integrator.
use glam::DVec3;

use super::test_meshes::{named_meshes, two_boxes};
use super::*;
use crate::camera::OrbitCamera;
use crate::tet::emission_absorption::{EmissionAbsorption, ExactRayIntegrator};
use crate::tet::optical::WorldView;
use crate::tet::procedural::box_mesh;
use crate::tet::scalar_integral::normalized_scalars;
use crate::transfer::TransferFunction;

/// Colour and transmittance agree this closely: the same stretches integrated by the same
/// rule, their ends computed by different f64 formulas (about 1e-15 apart).
const EA_TOLERANCE: f64 = 1e-9;

fn optics(density: f32) -> EmissionAbsorption {
    EmissionAbsorption::new(&TransferFunction::preset("cool-warm").unwrap(), density)
}

fn scalars(shell: &ShellMesh) -> Vec<f32> {
    normalized_scalars(&shell.mesh, None, "shell test").unwrap()
}

#[test]
fn emission_absorption_along_pixel_rays_equals_the_exact_integrator() {
    let camera = OrbitCamera {
        distance: 1.6,
        ..OrbitCamera::default()
    };
    let (w, h) = (20, 16);
    for (name, mesh) in named_meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        let normalized = scalars(&shell);
        // Dense enough that some rays terminate early.
        let optics = optics(40.0);
        let exact = ExactRayIntegrator::new(&shell.mesh, &normalized);
        let view = WorldView::new(&camera, w, h);
        for kind in LayoutKind::ALL {
            let integrator = ShellIntegrator::new(
                &shell,
                kind,
                &normalized,
                &optics,
                TraversalOptions::default(),
            )
            .unwrap();
            let mut stats = TraversalStats::default();
            let mut opaque = 0;
            for y in 0..h {
                for x in 0..w {
                    let (dir, near) = view.ray(x, y);
                    let ray = Ray {
                        origin: view.eye,
                        dir,
                        t_min: near,
                        t_max: f64::INFINITY,
                    };
                    let got = integrator.radiance(&ray, &mut stats);
                    let want = exact.integrate(&optics, view.eye, dir, (near, f64::INFINITY), true);
                    let diff = (got.colour - want.colour)
                        .abs()
                        .max(got.transmittance - want.transmittance)
                        .max(want.transmittance - got.transmittance)
                        .max_element();
                    assert!(
                        diff < EA_TOLERANCE,
                        "{name} {kind:?} pixel ({x}, {y}): {got:?} vs {want:?}"
                    );
                    opaque += usize::from(got.is_opaque());
                }
            }
            assert_eq!(stats.guard_hits(), 0, "{name} {kind:?}");
            if name == "box" {
                assert!(opaque > 0, "some rays terminate early");
            }
        }
    }
}

#[test]
fn the_reference_image_is_the_exact_integrators_from_outside_and_inside() {
    let mesh = box_mesh(3);
    let shell = ShellMesh::build(&mesh).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(3.0);
    for camera in [
        OrbitCamera::default(),
        OrbitCamera {
            distance: 0.3,
            ..OrbitCamera::default()
        },
    ] {
        image_matches_the_exact_integrator(&shell, &normalized, &optics, &camera);
    }
    let camera = OrbitCamera::default();
    let wrong_scalars = render_shell_reference(
        &shell,
        LayoutKind::Tet20,
        &[0.5],
        &optics,
        &camera,
        (4, 4),
        [0.0; 3],
    );
    assert!(wrong_scalars.is_err());
}

/// A flat tet's linear scalar is not finite; the stretch through it has no length and must
/// add nothing rather than poison the colour behind it.
#[test]
fn a_flat_tet_leaves_colours_finite() {
    let mut mesh = box_mesh(2);
    let centre = mesh.vertices.iter().position(|p| *p == [0.0; 3]).unwrap();
    mesh.vertices[centre] = [1.0, 1.0, 0.0];
    let shell = ShellMesh::build(&mesh).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(3.0);
    let integrator = ShellIntegrator::new(
        &shell,
        LayoutKind::Tet16,
        &normalized,
        &optics,
        TraversalOptions::default(),
    )
    .unwrap();
    let mut stats = TraversalStats::default();
    let camera = OrbitCamera::default();
    let view = WorldView::new(&camera, 24, 24);
    let mut seen = 0;
    for y in 0..24 {
        for x in 0..24 {
            let (dir, near) = view.ray(x, y);
            let ray = Ray {
                origin: view.eye,
                dir,
                t_min: near,
                t_max: f64::INFINITY,
            };
            let sum = integrator.radiance(&ray, &mut stats);
            assert!(
                sum.colour.is_finite() && sum.transmittance.is_finite(),
                "({x}, {y})"
            );
            seen += usize::from(sum.transmittance.x < 1.0);
        }
    }
    assert!(seen > 100 && stats.backward_steps > 0, "{seen} {stats:?}");
}

fn image_matches_the_exact_integrator(
    shell: &ShellMesh,
    normalized: &[f32],
    optics: &EmissionAbsorption,
    camera: &OrbitCamera,
) {
    let (w, h) = (32, 24);
    let background = [0.1, 0.2, 0.3];
    let render = render_shell_reference(
        shell,
        LayoutKind::Tet20,
        normalized,
        optics,
        camera,
        (w, h),
        background,
    )
    .unwrap();
    assert_eq!(render.stats.rays, u64::from(w * h));
    assert_eq!(render.stats.guard_hits(), 0);
    let exact = ExactRayIntegrator::new(&shell.mesh, normalized);
    let view = WorldView::new(camera, w, h);
    let mut want = crate::image::RgbaImage::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let (dir, near) = view.ray(x, y);
            let c = exact
                .integrate(optics, view.eye, dir, (near, f64::INFINITY), true)
                .over(glam::Vec3::from(background).as_dvec3());
            want.pixels[(y * w + x) as usize] =
                crate::shading::pack_rgba8([c.x as f32, c.y as f32, c.z as f32, 1.0]);
        }
    }
    let diff = render.image.compare(&want, 1);
    assert_eq!(diff.pixels_outside, 0, "{diff:?}");
    let background_pixel = crate::shading::pack_rgba8([0.1, 0.2, 0.3, 1.0]);
    let covered = render
        .image
        .pixels
        .iter()
        .filter(|&&p| p != background_pixel)
        .count();
    assert!(covered > 200, "{covered} pixels show the box");
}

#[test]
fn shadow_rays_see_the_transmittance_the_exact_integrator_sees() {
    let shell = ShellMesh::build(&two_boxes()).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(10.0);
    let exact = ExactRayIntegrator::new(&shell.mesh, &normalized);
    // World space: the boxes span -1/2 ≤ x ≤ -1/6 and 1/6 ≤ x ≤ 1/2, |y|, |z| ≤ 1/3.
    let below = DVec3::new(0.02, -0.8, 0.03);
    let inside = DVec3::new(-0.3, 0.01, -0.02);
    let cases = [
        // A ground point under the left box, the sun straight above.
        (
            below + DVec3::new(-0.3, 0.0, 0.0),
            Light::Directional(DVec3::Y),
        ),
        // Under the gap: nothing in the way.
        (below, Light::Directional(DVec3::Y)),
        // A point light inside the right box: only the part up to it counts.
        (
            below + DVec3::new(0.3, 0.0, 0.0),
            Light::Point(DVec3::new(0.3, 0.05, 0.03)),
        ),
        // From inside the left box towards a light beyond the right one.
        (inside, Light::Point(DVec3::new(1.5, 0.02, -0.01))),
        // The same towards a light in the gap.
        (inside, Light::Point(DVec3::new(0.0, 0.02, -0.01))),
    ];
    let mut results = Vec::new();
    for (point, light) in cases {
        let (got, stats) = shadow_transmittance(
            &shell,
            LayoutKind::Tet16,
            &normalized,
            &optics,
            point,
            light,
        )
        .unwrap();
        let (dir, t_max) = match light {
            Light::Point(p) => ((p - point).normalize(), point.distance(p)),
            Light::Directional(d) => (d, f64::INFINITY),
        };
        let want = exact
            .integrate(&optics, point, dir, (0.0, t_max), true)
            .transmittance;
        assert!(
            (got - want).abs().max_element() < EA_TOLERANCE,
            "{point} {light:?}: {got} vs {want}"
        );
        assert_eq!(stats.guard_hits(), 0);
        results.push(got);
    }
    assert!(
        results[0].max_element() < 0.9,
        "the box shadows the ground: {}",
        results[0]
    );
    assert_eq!(results[1], DVec3::ONE, "nothing shadows the gap");
    assert!(
        results[2].min_element() > results[0].min_element(),
        "half a box shadows less"
    );
    assert!(
        results[3].max_element() < results[4].min_element(),
        "two boxes shadow more than one"
    );
    assert!(results[4].max_element() < 1.0);
}

#[test]
fn distances_do_not_depend_on_the_length_of_the_direction() {
    let shell = ShellMesh::build(&box_mesh(3)).unwrap();
    let normalized = scalars(&shell);
    let optics = optics(5.0);
    let integrator = ShellIntegrator::new(
        &shell,
        LayoutKind::Tet32,
        &normalized,
        &optics,
        TraversalOptions::default(),
    )
    .unwrap();
    let mut stats = TraversalStats::default();
    let origin = DVec3::new(-0.9, 0.1, 0.05);
    let unit = DVec3::new(1.0, -0.15, 0.05).normalize();
    let ray = |dir: DVec3| Ray {
        origin,
        dir,
        t_min: 0.0,
        t_max: 0.7,
    };
    let a = integrator.radiance(&ray(unit), &mut stats);
    let b = integrator.radiance(&ray(unit * 7.5), &mut stats);
    assert!(a.transmittance.max_element() < 0.99);
    assert!((a.colour - b.colour).abs().max_element() < 1e-12);
    assert!((a.transmittance - b.transmittance).abs().max_element() < 1e-12);
    assert!((Ray::new(origin, unit * 3.0).dir - unit).length() < 1e-15);
}
