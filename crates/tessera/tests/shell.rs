//! Shell traversal (paper B) on the GPU against the CPU reference of `tessera_data::tet::shell`:
//! the tets each ray visits, images, shadow transmittance and the loop guard, for all three
//! tet layouts and both ways of tracing the shell (compute BVH walk, ray-tracing pipeline),
//! which must agree with each other exactly; and against interval shading (paper A) where the
//! optical models agree.
//!
//! The GPU decides in `f32` what the CPU decides in `f64`, so a ray passing within
//! [`EDGE_MARGIN`] of a tet edge may legitimately take the other side of it: such rays are left
//! out of the per-ray comparison, and their number is asserted to stay small.

mod common;

use common::camera;
use common::shell::{covered, gpu_image, in_box, layouts_and_paths, optics, paths, two_boxes};
use common::{assert_images_match, gpu, skip, Rng};
use glam::DVec3;
use tessera::path::Path;
use tessera::renderer::{self, RendererOptions, Technique};
use tessera::shaders;
use tessera::tet::interval::{GpuTetMesh, Integrand, Interval, IntervalOptions};
use tessera::tet::shell::{shadow_ray, GpuShellMesh, Shell, ShellOptions, ShellRays};
use tessera_data::scene::{Appearance, DataKind, Dataset, LoadOptions};
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::procedural::{box_mesh, ring_mesh, sphere_mesh};
use tessera_data::tet::scalar_integral::normalized_scalars;
use tessera_data::tet::shell::{
    build_layout, render_shell_reference, shadow_transmittance, trace_segments, LayoutKind, Light,
    Ray, ShellMesh, TraversalOptions, TraversalStats,
};
use tessera_data::tet::TetMesh;
use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction, TABLE_KNOTS};

/// World distance from a tet edge within which `f32` and `f64` edge predicates may disagree.
const EDGE_MARGIN: f64 = 1e-4;

fn meshes() -> Vec<(&'static str, TetMesh)> {
    vec![
        ("box", box_mesh(2)),
        ("two boxes", two_boxes()),
        ("ring", ring_mesh(3)),
    ]
}

/// Rays from a sphere around the mesh through points inside it, and rays from points inside
/// the mesh's bounding box (in a gap too, for the two boxes) in any direction.
fn test_rays(count: usize, seed: u64) -> Vec<(&'static str, Ray)> {
    let mut rng = Rng::new(seed);
    let mut rays = Vec::new();
    for _ in 0..count {
        let from = in_box(&mut rng, 1.0).normalize_or_zero() * 1.5;
        let towards = in_box(&mut rng, 0.4);
        rays.push(("outside", Ray::new(from, towards - from)));
    }
    for _ in 0..count {
        let from = in_box(&mut rng, 0.45);
        rays.push(("inside", Ray::new(from, in_box(&mut rng, 1.0))));
    }
    rays
}

/// Closest distance between the ray (over t >= t_min) and the segment p–q.
fn ray_segment_distance(ray: &Ray, p: DVec3, q: DVec3) -> f64 {
    // A point's distance to the ray is convex along the segment: a ternary search over the
    // segment parameter finds its minimum.
    let point_to_ray = |x: DVec3| {
        let t = (x - ray.origin).dot(ray.dir).max(ray.t_min);
        x.distance(ray.origin + ray.dir * t)
    };
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..60 {
        let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if point_to_ray(p.lerp(q, a)) < point_to_ray(p.lerp(q, b)) {
            hi = b;
        } else {
            lo = a;
        }
    }
    point_to_ray(p.lerp(q, 0.5 * (lo + hi)))
}

/// Whether the ray passes within [`EDGE_MARGIN`] of an edge of any tet.
fn grazes_an_edge(shell: &ShellMesh, ray: &Ray) -> bool {
    const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
    let world = shell.world();
    shell.mesh.tets.iter().any(|t| {
        EDGES.iter().any(|&(a, b)| {
            let (p, q) = (world[t[a] as usize], world[t[b] as usize]);
            ray_segment_distance(ray, p, q) < EDGE_MARGIN
        })
    })
}

/// The tets the CPU traversal visits along `ray`, each with its segment.
fn cpu_visits(
    shell: &ShellMesh,
    kind: LayoutKind,
    ray: &Ray,
    stats: &mut TraversalStats,
) -> Vec<(u32, u32)> {
    let layout = shell.layout(kind);
    trace_segments(shell, &*layout, ray, &TraversalOptions::default(), stats)
        .iter()
        .enumerate()
        .flat_map(|(s, seg)| seg.steps.iter().map(move |step| (step.tet, s as u32)))
        .collect()
}

#[test]
fn every_ray_visits_the_tets_the_cpu_traversal_visits() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let ways = paths(&gpu);
    let optics = optics(0.5);
    let rays = test_rays(60, 0x5eed_0001);
    for (name, mesh) in meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        let excluded: Vec<bool> = rays
            .iter()
            .map(|(_, r)| grazes_an_edge(&shell, r))
            .collect();
        let excluded_count = excluded.iter().filter(|&&e| e).count();
        let mut compute_traced = Vec::new();
        // Random rays come this close to an edge rarely: a few in a hundred.
        assert!(
            excluded_count * 20 <= rays.len(),
            "{name}: {excluded_count} of {} rays graze an edge",
            rays.len()
        );
        for (kind, path) in layouts_and_paths(&ways) {
            let options = ShellOptions::on(kind, path);
            let pass = ShellRays::new(&gpu, &compiler, &options, &optics).unwrap();
            let mesh = GpuShellMesh::upload_for(&gpu, &shell, kind, path).unwrap();
            let only_rays: Vec<Ray> = rays.iter().map(|(_, r)| *r).collect();
            let (traced, gpu_stats) = pass.trace(&gpu, &mesh, &only_rays).unwrap();
            // Both ways of tracing find the same faces: every ray, grazing ones too, gives
            // the same record, bit for bit.
            match path {
                Path::Compute => compute_traced = traced.clone(),
                Path::Graphics => assert!(
                    traced == compute_traced,
                    "{name} {kind:?}: the ray-tracing pipeline differs from the compute path"
                ),
            }
            let mut cpu_stats = TraversalStats::default();
            let (mut compared, mut crossing, mut two_segments) = (0, 0, 0);
            for (i, ((from, ray), got)) in rays.iter().zip(&traced).enumerate() {
                let want = cpu_visits(&shell, kind, ray, &mut cpu_stats);
                if excluded[i] {
                    continue;
                }
                let got: Vec<(u32, u32)> = got.visited.iter().map(|v| (v.tet, v.segment)).collect();
                assert_eq!(got, want, "{name}, {kind:?}, ray {i} from {from}: {ray:?}");
                assert_eq!(traced[i].result.steps as usize, want.len());
                compared += 1;
                crossing += usize::from(!want.is_empty());
                two_segments += usize::from(want.last().is_some_and(|v| v.1 > 0));
            }
            assert_eq!(gpu_stats.rays, rays.len() as u64, "{name} {kind:?}");
            assert_eq!(gpu_stats.guard_hits(), 0, "{name} {kind:?}: {gpu_stats:?}");
            assert_eq!(cpu_stats.guard_hits(), 0, "{name} {kind:?}: {cpu_stats:?}");
            // The rays exercise what they are meant to: most cross the mesh, and some cross
            // the gap between the boxes.
            assert!(
                crossing * 2 > compared,
                "{name} {kind:?}: {crossing}/{compared}"
            );
            if name != "box" {
                assert!(two_segments > 0, "{name} {kind:?}: no ray crossed the gap");
            }
            eprintln!(
                "{name} {kind:?} {}: {compared} rays equal ({crossing} crossing, {two_segments} \
                 with two segments), {excluded_count} excluded; GPU {gpu_stats:?}",
                path.name()
            );
        }
    }
}

#[test]
fn images_equal_the_cpu_reference_from_outside_and_inside() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let ways = paths(&gpu);
    let size = (40, 32);
    let background = [0.9, 0.9, 0.85];
    // Dense enough that rays through the middle terminate early.
    let optics = optics(30.0);
    let views = [
        ("outside", camera(33.0, 21.0, 2.2)),
        ("inside", camera(-47.0, 12.0, 0.3)),
    ];
    let mut meshes = meshes();
    meshes.push(("sphere", sphere_mesh(3)));
    for (name, mesh) in meshes {
        let shell = ShellMesh::build(&mesh).unwrap();
        let normalized = normalized_scalars(&shell.mesh, None, name).unwrap();
        let mut compute_images = [None, None];
        for (kind, path) in layouts_and_paths(&ways) {
            let options = ShellOptions::on(kind, path);
            let pass = Shell::new(&gpu, &compiler, &options, &optics).unwrap();
            let gpu_mesh = GpuShellMesh::upload_for(&gpu, &shell, kind, path).unwrap();
            for (v, (where_from, camera)) in views.iter().enumerate() {
                let reference = render_shell_reference(
                    &shell,
                    kind,
                    &normalized,
                    &optics,
                    camera,
                    size,
                    background,
                )
                .unwrap();
                let (image, stats) = gpu_image(&gpu, &pass, &gpu_mesh, camera, size, background);
                let label = format!("shell-{name}-{}-{}-{where_from}", kind.name(), path.name())
                    .replace(' ', "-");
                match path {
                    Path::Compute => compute_images[v] = Some((image.clone(), stats)),
                    Path::Graphics => assert_eq!(
                        Some((&image, &stats)),
                        compute_images[v].as_ref().map(|(i, s)| (i, s)),
                        "{label}: the ray-tracing pipeline differs from the compute path"
                    ),
                }
                // The same stretches in f32: colours within 1/255 but for rays along an edge.
                assert_images_match(&label, &image, &reference.image, 1, 0.995);
                assert!(covered(&image, background) > 0.2, "{label}: little drawn");
                assert_eq!(stats.rays, u64::from(size.0 * size.1), "{label}");
                assert_eq!(stats.guard_hits(), 0, "{label}: {stats:?}");
                assert_eq!(stats.unmatched_exits, 0, "{label}: {stats:?}");
                // Early termination shortens rays on both sides alike.
                let (got, want) = (stats.steps as f64, reference.stats.steps as f64);
                assert!(
                    (got - want).abs() <= 0.01 * want + 4.0,
                    "{label}: {got} steps against {want}"
                );
            }
        }
    }
}

/// A neighbour table that glues the first and second tet of a ray's path to themselves sends
/// the walk back and forth; the guard must end it and count it, on the GPU as on the CPU.
#[test]
fn the_loop_guard_ends_a_circling_walk_and_counts_it() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let ways = paths(&gpu);
    let optics = optics(0.5);
    let shell = ShellMesh::build(&box_mesh(2)).unwrap();
    let ray = Ray::new(
        DVec3::new(-1.0, 0.013, 0.021),
        DVec3::new(1.0, 0.011, -0.007).normalize(),
    );
    let traversal = TraversalOptions {
        max_steps_per_segment: 50,
    };
    let clean = shell.layout(LayoutKind::Tet32);
    let mut stats = TraversalStats::default();
    let path = trace_segments(&shell, &*clean, &ray, &traversal, &mut stats);
    let steps = &path[0].steps;
    assert!(steps.len() > 3);
    let face_of = |tet: u32, face: [u32; 3]| {
        let t = shell.mesh.tets[tet as usize];
        (0..4).find(|&f| !face.contains(&t[f])).unwrap()
    };
    let mut glued = shell.neighbours.clone();
    let (first, second) = (steps[0].tet, steps[1].tet);
    glued[first as usize][face_of(first, steps[0].entered_face)] = first;
    glued[second as usize][face_of(second, steps[2].entered_face)] = second;
    for (kind, path) in layouts_and_paths(&ways) {
        let layout = build_layout(kind, &shell.mesh.tets, &glued);
        let options = ShellOptions {
            traversal,
            ..ShellOptions::on(kind, path)
        };
        let mut cpu_stats = TraversalStats::default();
        trace_segments(&shell, &*layout, &ray, &traversal, &mut cpu_stats);
        let mesh = GpuShellMesh::upload_layout(&gpu, &shell, &*layout, path).unwrap();
        let pass = ShellRays::new(&gpu, &compiler, &options, &optics).unwrap();
        let (_, gpu_stats) = pass.trace(&gpu, &mesh, &[ray]).unwrap();
        assert!(gpu_stats.guard_hits() >= 1, "{kind:?}: {gpu_stats:?}");
        assert_eq!(gpu_stats.step_limits, cpu_stats.step_limits, "{kind:?}");
        assert_eq!(gpu_stats.dead_ends, cpu_stats.dead_ends, "{kind:?}");
        // A whole image over the corrupt mesh ends too, with the guard counted.
        let image = Shell::new(&gpu, &compiler, &options, &optics).unwrap();
        let (_, stats) = gpu_image(
            &gpu,
            &image,
            &mesh,
            &camera(90.0, 0.0, 2.0),
            (24, 24),
            [0.0; 3],
        );
        assert!(stats.guard_hits() >= 1, "{kind:?} image: {stats:?}");
        eprintln!(
            "{kind:?} {}: ray {gpu_stats:?}; image {stats:?}",
            path.name()
        );
    }
}

#[test]
fn shadow_transmittance_equals_the_cpu_reference() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let ways = paths(&gpu);
    let optics = optics(6.0);
    let shell = ShellMesh::build(&two_boxes()).unwrap();
    let normalized = normalized_scalars(&shell.mesh, None, "two boxes").unwrap();
    let lights = [
        Light::Directional(DVec3::new(1.0, 0.31, 0.17)),
        Light::Directional(DVec3::new(-0.2, 1.0, 0.43)),
        Light::Point(DVec3::new(0.9, 0.23, -0.11)),
        // Inside the volume: the ray ends there.
        Light::Point(DVec3::new(0.31, 0.07, 0.05)),
    ];
    let mut rng = Rng::new(0x5eed_0002);
    let points: Vec<DVec3> = (0..24).map(|_| in_box(&mut rng, 0.7)).collect();
    for (kind, path) in layouts_and_paths(&ways) {
        let options = ShellOptions::on(kind, path);
        let pass = ShellRays::new(&gpu, &compiler, &options, &optics).unwrap();
        let mut mesh = GpuShellMesh::upload_for(&gpu, &shell, kind, path).unwrap();
        mesh.scalar_range = tessera_data::tet::scalar_integral::scalar_range(&shell.mesh).unwrap();
        let mut rays = Vec::new();
        let mut want = Vec::new();
        for &light in &lights {
            for &point in &points {
                rays.push(shadow_ray(point, light));
                let (t, _) =
                    shadow_transmittance(&shell, kind, &normalized, &optics, point, light).unwrap();
                want.push(t);
            }
        }
        let (traced, _) = pass.trace(&gpu, &mesh, &rays).unwrap();
        let mut shadowed = 0;
        for (i, (got, want)) in traced.iter().zip(&want).enumerate() {
            let got = DVec3::from(got.result.transmittance.map(f64::from));
            if grazes_an_edge(&shell, &rays[i]) {
                continue;
            }
            assert!(
                (got - *want).abs().max_element() < 1e-4,
                "{kind:?} ray {i}: {got} against {want}"
            );
            // Rays that did not turn opaque cross the tets up to the light, and no further.
            if want.max_element() > 0.05 {
                let mut stats = TraversalStats::default();
                let steps = cpu_visits(&shell, kind, &rays[i], &mut stats).len();
                assert_eq!(traced[i].result.steps as usize, steps, "{kind:?} ray {i}");
            }
            shadowed += usize::from(want.max_element() < 0.9);
        }
        assert!(shadowed > 5, "{kind:?}: only {shadowed} points in shadow");
    }
}

/// Interval shading of the same mesh where the optical models agree: pure absorption (the
/// background dimmed by the optical depth) and pure emission (light added to it), with
/// densities low enough that early termination does not cut the shell rays short.
#[test]
fn pure_absorption_and_pure_emission_images_equal_interval_shading() {
    let gpu = gpu();
    let caps = gpu.caps().clone();
    let path = if caps.buffer_float32_atomic_add {
        Path::Compute
    } else if caps.mesh_shader {
        Path::Graphics
    } else {
        skip("", "interval shading runs on neither path here");
        return;
    };
    let compiler = shaders::compiler();
    let tf = TransferFunction::preset("cool-warm").unwrap();
    let density = 1.5;
    let zero = IntegrandTable {
        values: vec![[0.0; 3]; TABLE_KNOTS],
    };
    let size = (40, 32);
    let camera = camera(33.0, 21.0, 2.2);
    let mesh = sphere_mesh(3);
    let shell = ShellMesh::build(&mesh).unwrap();
    for (mode, background) in [
        (ScalarMode::Absorption, [0.9, 0.9, 0.85]),
        (ScalarMode::Emission, [0.05, 0.05, 0.1]),
    ] {
        let table = IntegrandTable::new(&tf, mode, density, TABLE_KNOTS);
        let optics = match mode {
            ScalarMode::Absorption => EmissionAbsorption {
                absorption: table.clone(),
                emission: zero.clone(),
            },
            _ => EmissionAbsorption {
                absorption: zero.clone(),
                emission: table.clone(),
            },
        };
        let interval = Interval::new(
            &gpu,
            &compiler,
            &IntervalOptions {
                integrand: Integrand::Scalar { mode, table },
                ..IntervalOptions::new(path)
            },
        )
        .unwrap();
        let interval_mesh = GpuTetMesh::upload(&gpu, &mesh).unwrap();
        let (want, _) = interval
            .render_image(&gpu, &interval_mesh, &camera, size, background)
            .unwrap();
        let pass = Shell::new(
            &gpu,
            &compiler,
            &ShellOptions::new(LayoutKind::Tet20),
            &optics,
        )
        .unwrap();
        let shell_mesh = GpuShellMesh::upload(&gpu, &shell, LayoutKind::Tet20).unwrap();
        let (got, stats) = gpu_image(&gpu, &pass, &shell_mesh, &camera, size, background);
        assert_eq!(stats.guard_hits(), 0, "{stats:?}");
        // Interval shading rasterizes proxies: pixels on a projected tet edge may differ.
        assert_images_match(&format!("shell-vs-interval-{mode:?}"), &got, &want, 2, 0.97);
        assert!(covered(&got, background) > 0.2, "{mode:?}: little drawn");
    }
}

/// `Technique::Shell` behind the front door draws the look's emission–absorption of the mesh
/// (the CPU reference's image) in each layout, changes its look without uploading anything,
/// and refuses what it cannot draw with a reason.
#[test]
fn the_front_door_draws_tets_in_each_layout_and_refuses_what_it_cannot() {
    let gpu = gpu();
    let data = Dataset::load("tets:box:3", &LoadOptions::default()).unwrap();
    let Dataset::Tets(tets) = &data else {
        unreachable!()
    };
    let shell = ShellMesh::build(&tets.mesh).unwrap();
    let normalized = normalized_scalars(&shell.mesh, None, "box").unwrap();
    let camera = camera(33.0, 21.0, 1.9);
    let size = (48, 32);
    let look = Appearance::default();
    let background = look.background(DataKind::Tets, None);
    let optics = EmissionAbsorption::new(&look.transfer, look.density);
    for kind in LayoutKind::ALL {
        let options = RendererOptions {
            layout: kind,
            ..RendererOptions::default()
        };
        let mut r = renderer::create(&gpu, Technique::Shell, &options).unwrap();
        r.set_appearance(&gpu, &look).unwrap();
        r.set_data(&gpu, &data).unwrap();
        let through = renderer::render_image(&gpu, r.as_mut(), &camera, size).unwrap();
        let reference = render_shell_reference(
            &shell,
            kind,
            &normalized,
            &optics,
            &camera,
            size,
            background,
        )
        .unwrap();
        let label = format!("shell-front-door-{}", kind.name());
        assert_images_match(&label, &through.image, &reference.image, 1, 0.995);
        assert_eq!(
            through.times.scopes.first().map(|s| s.0.as_str()),
            Some("shell traversal")
        );
        assert_eq!(through.stats.details["guard_step_limits"], 0);
        assert!(through.stats.details["tet_steps"] > 0);
        // The float radiance behind the colours: each 8-bit channel is it clamped and
        // rounded, and it differs from the background where the mesh is.
        let radiance = r.accumulated(&gpu).unwrap().unwrap();
        assert_eq!(radiance.quantity_name(), "radiance");
        assert_eq!((radiance.width, radiance.height), size);
        let mut lit = 0;
        for (value, &packed) in radiance.values.iter().zip(&through.image.pixels) {
            for (c, &v) in value.iter().enumerate() {
                let byte = (packed >> (8 * c)) & 0xff;
                assert_eq!(
                    byte,
                    (v.clamp(0.0, 1.0) * 255.0).round() as u32,
                    "{value:?}"
                );
            }
            lit += usize::from((0..3).any(|c| (value[c] - background[c]).abs() > 1e-3));
        }
        assert!(
            lit * 5 > radiance.values.len(),
            "{lit} pixels differ from the background"
        );
        // A new look is a table write and a push constant.
        let before = r.counters();
        let denser = Appearance {
            density: 12.0,
            range: Some((0.0, 2.0)),
            ..look.clone()
        };
        r.set_appearance(&gpu, &denser).unwrap();
        assert_eq!(r.counters(), before);
        let darker = renderer::render_image(&gpu, r.as_mut(), &camera, size).unwrap();
        assert_ne!(darker.image, through.image);
    }
    let mut r = renderer::create(&gpu, Technique::Shell, &RendererOptions::default()).unwrap();
    let field = Dataset::load("tets:asteroids:4", &LoadOptions::default()).unwrap();
    let err = r.set_data(&gpu, &field).unwrap_err().to_string();
    assert!(err.contains("interval"), "{err}");
    let mut bare = tets.clone();
    bare.mesh.scalars = None;
    let err = r
        .set_data(&gpu, &Dataset::Tets(bare))
        .unwrap_err()
        .to_string();
    assert!(err.contains("scalars"), "{err}");
    let volume = Dataset::load("procedural:sphere:8", &LoadOptions::default()).unwrap();
    assert!(r.set_data(&gpu, &volume).is_err());
    assert_eq!(Technique::parse("shell").unwrap(), Technique::Shell);
    assert_eq!(Technique::Shell.draws(), DataKind::Tets);
    let tet16 = RendererOptions {
        layout: LayoutKind::Tet16,
        ..RendererOptions::default()
    };
    assert_eq!(tet16.ignored_by(Technique::Interval), ["layout"]);
    assert!(tet16.ignored_by(Technique::Shell).is_empty());
}
