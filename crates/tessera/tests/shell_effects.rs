//! Shell traversal's secondary-ray effects (paper B, §6) on the GPU against the CPU reference
//! of `tessera_data::tet::shell`: the per-tet lighting (gradients, shadow and AO
//! transmittance), images with shadows and a ground plane, with AO and with gradient shading,
//! the front door's timers and counters, and a shadow that darkens what it should.
//!
//! Tolerances: the GPU marches in `f32` what the CPU marches in `f64`, from centroids and
//! along directions that differ in their last bits, so per-tet transmittances agree to about
//! 1e-5; a secondary ray that passes within rounding of a tet edge may take the other tet and
//! still cross nearly the same lengths, and one that turns opaque stops (early termination at
//! 98 %) a step apart, which moves its transmittance by at most 0.02. Images therefore match
//! within 2/255 on all but a few pixels (those of such rays, and ground-plane edges that
//! `f32` and `f64` put one pixel apart).

mod common;

use common::camera;
use common::shell::{optics, two_boxes};
use common::{assert_clean, assert_images_match, gpu, skip, Need};
use glam::DVec3;
use tessera::path::Path;
use tessera::renderer::{self, AmbientOcclusion, Light, RendererOptions, Technique};
use tessera::shaders;
use tessera::tet::shell::{EffectBuffers, GpuShellMesh, Shell, ShellOptions};
use tessera_data::scene::{Appearance, DataKind, Dataset, LoadOptions};
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::procedural::sphere_mesh;
use tessera_data::tet::scalar_integral::normalized_scalars;
use tessera_data::tet::shell::{
    render_shell_effects_reference, render_shell_reference, GroundPlane, LayoutKind, ShellEffects,
    ShellMesh, ShellScene, TetLighting, GROUND_ALBEDO, VOLUME_AMBIENT,
};
use tessera_data::{OrbitCamera, RgbaImage, View};

fn ao(samples: u32, radius: f32) -> Option<AmbientOcclusion> {
    Some(AmbientOcclusion::new(samples, radius).unwrap())
}

/// The effects each test image shows, by name.
fn effect_sets() -> Vec<(&'static str, ShellEffects)> {
    let none = ShellEffects::default();
    vec![
        (
            "sun",
            ShellEffects {
                shadows: Some(Light::above(DVec3::Y)),
                ..none
            },
        ),
        (
            "point-light",
            ShellEffects {
                shadows: Some(Light::Point(DVec3::new(0.45, 0.6, 0.2))),
                ..none
            },
        ),
        (
            "ao",
            ShellEffects {
                ambient_occlusion: ao(8, 0.25),
                ..none
            },
        ),
        (
            "gradient",
            ShellEffects {
                gradient: true,
                ..none
            },
        ),
        (
            "all",
            ShellEffects {
                shadows: Some(Light::Directional(DVec3::new(-0.4, 1.0, 0.3))),
                ambient_occlusion: ao(4, 0.2),
                gradient: true,
            },
        ),
    ]
}

/// How many entries of `got` differ from `want` by more than `tolerance` in some component.
fn outliers(got: &[DVec3], want: &[DVec3], tolerance: f64) -> (usize, f64) {
    assert_eq!(got.len(), want.len());
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for (g, w) in got.iter().zip(want) {
        let d = (*g - *w).abs().max_element();
        worst = worst.max(d);
        count += usize::from(d > tolerance);
    }
    (count, worst)
}

#[test]
fn per_tet_lighting_equals_the_cpu_reference() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let optics = optics(8.0);
    let size = (24, 20);
    let camera = camera(30.0, 25.0, 2.0);
    for (name, mesh) in [("two-boxes", two_boxes()), ("sphere", sphere_mesh(3))] {
        let shell = ShellMesh::build(&mesh).unwrap();
        let normalized = normalized_scalars(&shell.mesh, None, name).unwrap();
        for (what, effects) in effect_sets() {
            let kind = LayoutKind::Tet16;
            let scene = ShellScene {
                shell: &shell,
                kind,
                normalized: &normalized,
                optics: &optics,
                effects: &effects,
            };
            let want = render_shell_effects_reference(&scene, &camera, size, [0.0; 3]).unwrap();
            let options = ShellOptions::new(kind);
            let pass = Shell::with_effects(&gpu, &compiler, &options, &optics, &effects).unwrap();
            let mesh = GpuShellMesh::upload(&gpu, &shell, kind).unwrap();
            let pixels = u64::from(size.0 * size.1);
            let buffers = EffectBuffers::new(&gpu, &shell, &effects, pixels).unwrap();
            let got = pass
                .render_effects_image(
                    &gpu, &mesh, &buffers, &shell, &optics, &camera, size, [0.0; 3],
                )
                .unwrap();
            let lighting: TetLighting = buffers.read_lighting(&gpu).unwrap();
            let label = format!("{name} {what}");
            let tets = shell.mesh.tets.len();
            // Gradients: the same 3×3 solve in f32; relative to their size.
            let scale = want
                .lighting
                .gradients
                .iter()
                .fold(0.0f64, |m, g| m.max(g.length()));
            let (bad, worst) =
                outliers(&lighting.gradients, &want.lighting.gradients, 1e-4 * scale);
            assert_eq!(bad, 0, "{label}: gradients off by up to {worst}");
            for (list, cpu, what_list) in [
                (&lighting.light, &want.lighting.light, "light"),
                (&lighting.occlusion, &want.lighting.occlusion, "occlusion"),
            ] {
                let (bad, worst) = outliers(list, cpu, 1e-3);
                assert!(
                    bad * 100 <= tets && worst < 0.03,
                    "{label}: {bad} of {tets} tets' {what_list} off, by up to {worst}"
                );
            }
            // One shadow ray per tet and per ground pixel; the ground's edge may move a pixel.
            let ground = |s: u64| {
                s.saturating_sub(if effects.shadows.is_some() {
                    tets as u64
                } else {
                    0
                })
            };
            let (g, w) = (
                ground(got.secondary.shadow_rays),
                ground(want.secondary.shadow_rays),
            );
            assert!(
                g.abs_diff(w) <= 2 + w / 50,
                "{label}: {g} ground rays against {w}"
            );
            assert_eq!(got.secondary.ao_rays, want.secondary.ao_rays, "{label}");
            assert_eq!(got.secondary.guard_hits, 0, "{label}");
            assert_eq!(got.stats.guard_hits(), 0, "{label}");
            let steps = |s: u64| s as f64;
            assert!(
                (steps(got.secondary.steps) - steps(want.secondary.steps)).abs()
                    <= 0.01 * steps(want.secondary.steps) + 8.0,
                "{label}: {} secondary steps against {}",
                got.secondary.steps,
                want.secondary.steps
            );
            // Each effect has its pass and timer, the pixel pass last.
            let scopes: Vec<&str> = got.times.iter().map(|s| s.0.as_str()).collect();
            assert_eq!(scopes.last(), Some(&"shell traversal"), "{label}");
            assert_eq!(
                scopes.contains(&"shell shadows"),
                effects.shadows.is_some(),
                "{label}: {scopes:?}"
            );
            assert_eq!(
                scopes.contains(&"shell ambient occlusion"),
                effects.ambient_occlusion.is_some(),
                "{label}: {scopes:?}"
            );
            assert_clean(&gpu);
        }
    }
}

#[test]
fn images_with_each_effect_equal_the_cpu_reference() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let optics = optics(10.0);
    let size = (48, 36);
    let background = [0.1, 0.1, 0.15];
    let views = [
        ("outside", camera(33.0, 28.0, 2.4)),
        ("inside", camera(-47.0, 12.0, 0.3)),
    ];
    for (name, mesh) in [("two-boxes", two_boxes()), ("sphere", sphere_mesh(3))] {
        let shell = ShellMesh::build(&mesh).unwrap();
        let normalized = normalized_scalars(&shell.mesh, None, name).unwrap();
        // The layouts take turns: each is exercised, and each effect in two of them.
        for (i, (what, effects)) in effect_sets().into_iter().enumerate() {
            let turn = i + usize::from(name == "sphere");
            let kind = LayoutKind::ALL[turn % LayoutKind::ALL.len()];
            let options = ShellOptions::new(kind);
            let pass = Shell::with_effects(&gpu, &compiler, &options, &optics, &effects).unwrap();
            let mesh = GpuShellMesh::upload(&gpu, &shell, kind).unwrap();
            let pixels = u64::from(size.0 * size.1);
            let buffers = EffectBuffers::new(&gpu, &shell, &effects, pixels).unwrap();
            let scene = ShellScene {
                shell: &shell,
                kind,
                normalized: &normalized,
                optics: &optics,
                effects: &effects,
            };
            let mut changed = 0;
            for (where_from, camera) in &views {
                let want =
                    render_shell_effects_reference(&scene, camera, size, background).unwrap();
                let got = pass
                    .render_effects_image(
                        &gpu, &mesh, &buffers, &shell, &optics, camera, size, background,
                    )
                    .unwrap();
                let label = format!("shell-fx-{name}-{what}-{}-{where_from}", kind.name());
                assert_images_match(&label, &got.image, &want.image, 2, 0.99);
                // The comparison means something only where the effect shows (gradient
                // shading only in dense regions, which the view from inside may miss).
                let plain = render_shell_reference(
                    &shell,
                    kind,
                    &normalized,
                    &optics,
                    camera,
                    size,
                    background,
                )
                .unwrap();
                changed += plain.image.compare(&want.image, 2).pixels_outside;
                assert_eq!(got.stats.rays, pixels, "{label}");
                assert_eq!(got.stats.guard_hits(), 0, "{label}");
            }
            assert!(
                changed > 20,
                "{name} {what}: the effect changes {changed} pixels"
            );
        }
    }
    assert_clean(&gpu);
}

/// The front door: without effects the same image, scopes and counters as before; with them
/// a timer per effect, counts of secondary rays and the CPU reference's image.
#[test]
fn the_front_door_times_each_effect_and_counts_its_rays() {
    let gpu = gpu();
    let data = Dataset::load("tets:box:3", &LoadOptions::default()).unwrap();
    let Dataset::Tets(tets) = &data else {
        unreachable!()
    };
    let shell = ShellMesh::build(&tets.mesh).unwrap();
    let normalized = normalized_scalars(&shell.mesh, None, "box").unwrap();
    let camera = camera(33.0, 25.0, 2.2);
    let size = (48, 32);
    let look = Appearance::default();
    let background = look.background(DataKind::Tets, None);
    let optics = EmissionAbsorption::new(&look.transfer, look.density);
    let render = |options: &RendererOptions| {
        let mut r = renderer::create(&gpu, Technique::Shell, options).unwrap();
        r.set_appearance(&gpu, &look).unwrap();
        r.set_data(&gpu, &data).unwrap();
        renderer::render_image(&gpu, r.as_mut(), &camera, size).unwrap()
    };
    // Effects off: the plain pass, exactly as `Shell::new` draws it.
    let plain = render(&RendererOptions::default());
    let scopes = |r: &renderer::RenderedImage| -> Vec<String> {
        r.times.scopes.iter().map(|s| s.0.clone()).collect()
    };
    assert_eq!(scopes(&plain), ["shell traversal"]);
    assert!(!plain.stats.details.contains_key("shadow_rays"));
    let compiler = shaders::compiler();
    let direct = Shell::new(
        &gpu,
        &compiler,
        &ShellOptions::new(LayoutKind::Tet20),
        &optics,
    )
    .unwrap();
    let mut mesh = GpuShellMesh::upload(&gpu, &shell, LayoutKind::Tet20).unwrap();
    mesh.scalar_range =
        tessera_data::tet::scalar_integral::mapping_range(&tets.mesh, look.range, "box").unwrap();
    let (image, _, _) = direct
        .render_image(&gpu, &mesh, &camera, size, background)
        .unwrap();
    assert_eq!(
        plain.image, image,
        "effects off draw the plain pass's image"
    );

    let samples = 6;
    let options = RendererOptions {
        shadows: Some(Light::above(DVec3::Y)),
        ao: ao(samples, 0.15),
        gradient: true,
        ..RendererOptions::default()
    };
    let lit = render(&options);
    assert_eq!(
        scopes(&lit),
        [
            "shell gradients",
            "shell ambient occlusion",
            "shell shadows",
            "shell ground",
            "shell traversal"
        ]
    );
    assert!(lit.times.scopes.iter().all(|s| s.1 >= 0.0));
    let details = &lit.stats.details;
    let tet_count = shell.mesh.tets.len() as u64;
    assert_eq!(details["ao_rays"], u64::from(samples) * tet_count);
    assert!(details["shadow_rays"] > tet_count, "{details:?}");
    assert!(details["secondary_steps"] > details["shadow_rays"]);
    assert_eq!(details["secondary_guard_hits"], 0);
    let effects = options.shell_effects();
    let scene = ShellScene {
        shell: &shell,
        kind: LayoutKind::Tet20,
        normalized: &normalized,
        optics: &optics,
        effects: &effects,
    };
    let want = render_shell_effects_reference(&scene, &camera, size, background).unwrap();
    assert_images_match("shell-fx-front-door", &lit.image, &want.image, 2, 0.99);
    assert_ne!(lit.image, plain.image);
    assert_clean(&gpu);
}

/// The per-tet lighting does not depend on the eye: the front door casts the tets' shadow and
/// AO rays in the first frame and reuses them while the mesh, the look and the light stay, and
/// a reused frame equals a freshly lit one, from another view too; a new look lights again.
#[test]
fn the_front_door_lights_the_tets_once_until_the_look_changes() {
    let gpu = gpu();
    let data = Dataset::load("tets:box:3", &LoadOptions::default()).unwrap();
    let size = (40, 30);
    let options = RendererOptions {
        shadows: Some(Light::above(DVec3::Y)),
        ao: ao(4, 0.15),
        gradient: true,
        ..RendererOptions::default()
    };
    let look = Appearance::default();
    let fresh = |camera: &OrbitCamera, look: &Appearance| {
        let mut r = renderer::create(&gpu, Technique::Shell, &options).unwrap();
        r.set_appearance(&gpu, look).unwrap();
        r.set_data(&gpu, &data).unwrap();
        renderer::render_image(&gpu, r.as_mut(), camera, size).unwrap()
    };
    let mut r = renderer::create(&gpu, Technique::Shell, &options).unwrap();
    r.set_appearance(&gpu, &look).unwrap();
    r.set_data(&gpu, &data).unwrap();
    let (near, far) = (camera(33.0, 25.0, 2.2), camera(-70.0, 10.0, 2.6));
    let first = renderer::render_image(&gpu, r.as_mut(), &near, size).unwrap();
    let ao_rays = |f: &renderer::RenderedImage| f.stats.details["ao_rays"];
    assert!(ao_rays(&first) > 0);
    let again = renderer::render_image(&gpu, r.as_mut(), &near, size).unwrap();
    assert_eq!(ao_rays(&again), 0, "the second frame cast AO rays again");
    assert!(again.stats.details["shadow_rays"] < first.stats.details["shadow_rays"]);
    assert_eq!(again.image, first.image);
    // The lighting scopes stay in every frame, so frames line up in benchmarks.
    assert_eq!(again.times.scopes.len(), first.times.scopes.len());
    let turned = renderer::render_image(&gpu, r.as_mut(), &far, size).unwrap();
    assert_eq!(ao_rays(&turned), 0);
    assert_eq!(
        turned.image,
        fresh(&far, &look).image,
        "reused lighting from another view"
    );
    let denser = Appearance {
        density: look.density * 3.0,
        ..look.clone()
    };
    r.set_appearance(&gpu, &denser).unwrap();
    let relit = renderer::render_image(&gpu, r.as_mut(), &far, size).unwrap();
    assert!(
        ao_rays(&relit) > 0,
        "a new look did not light the tets again"
    );
    assert_eq!(relit.image, fresh(&far, &denser).image);
    assert_ne!(relit.image, turned.image);
    assert_clean(&gpu);
}

/// A ray–box test (slab method): whether `origin + t dir`, `t > 0`, meets the box.
fn meets_box(origin: DVec3, dir: DVec3, (lo, hi): (DVec3, DVec3)) -> bool {
    let (mut near, mut far) = (0.0f64, f64::INFINITY);
    for a in 0..3 {
        let (t0, t1) = ((lo[a] - origin[a]) / dir[a], (hi[a] - origin[a]) / dir[a]);
        near = near.max(t0.min(t1));
        far = far.min(t0.max(t1));
    }
    near <= far
}

/// The mean red byte of `pixels` in `image`.
fn mean_red(image: &RgbaImage, pixels: &[usize]) -> f64 {
    let sum: f64 = pixels
        .iter()
        .map(|&i| f64::from(image.pixels[i] & 0xff))
        .sum();
    sum / pixels.len() as f64
}

/// The volume's shadow on the ground: ground pixels whose shadow ray passes through the mesh
/// are darker than those whose does not, which show the ground's full lit colour.
#[test]
fn a_shadow_darkens_the_ground() {
    let gpu = gpu();
    let data = Dataset::load("tets:box:3", &LoadOptions::default()).unwrap();
    let Dataset::Tets(tets) = &data else {
        unreachable!()
    };
    let shell = ShellMesh::build(&tets.mesh).unwrap();
    let bounds = shell.world_bounds();
    let camera = camera(20.0, 50.0, 2.6);
    let size = (64, 48);
    let view = View::of_unit_box(&camera, size);
    // The sun behind the box as the camera sees it, so the shadow falls towards the camera.
    let behind = -view.eye.as_dvec3() * DVec3::new(1.0, 0.0, 1.0);
    let sun = (behind.normalize() * 0.7 + DVec3::Y).normalize();
    let options = RendererOptions {
        shadows: Some(Light::Directional(sun)),
        ..RendererOptions::default()
    };
    let look = Appearance {
        density: 30.0,
        background: Some([0.0, 0.0, 0.0]),
        ..Appearance::default()
    };
    let mut r = renderer::create(&gpu, Technique::Shell, &options).unwrap();
    r.set_appearance(&gpu, &look).unwrap();
    r.set_data(&gpu, &data).unwrap();
    let got = renderer::render_image(&gpu, r.as_mut(), &camera, size).unwrap();
    // Classify the pixels that see the ground and not the mesh, by their pixel rays.
    let plane = GroundPlane::below(bounds, DVec3::Y);
    let (mut shadowed, mut lit) = (Vec::new(), Vec::new());
    for y in 0..size.1 {
        for x in 0..size.0 {
            let sx = (2.0 * (x as f32 + 0.5) / size.0 as f32 - 1.0) * view.tan_half_fov.x;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / size.1 as f32) * view.tan_half_fov.y;
            let dir = (view.forward + sx * view.right + sy * view.up)
                .normalize()
                .as_dvec3();
            let eye = view.eye.as_dvec3();
            let Some(t) = plane.hit(eye, dir, 0.0) else {
                continue;
            };
            // A margin keeps pixels at the edges of the box and the shadow out.
            let grown = (bounds.0 - DVec3::splat(0.03), bounds.1 + DVec3::splat(0.03));
            let shrunk = (bounds.0 + DVec3::splat(0.05), bounds.1 - DVec3::splat(0.05));
            if meets_box(eye, dir, grown) {
                continue;
            }
            let ground = eye + dir * t;
            let i = (y * size.0 + x) as usize;
            if meets_box(ground, sun, shrunk) {
                shadowed.push(i);
            } else if !meets_box(ground, sun, grown) {
                lit.push(i);
            }
        }
    }
    assert!(
        shadowed.len() > 20 && lit.len() > 20,
        "{} shadowed, {} lit",
        shadowed.len(),
        lit.len()
    );
    let (dark, bright) = (mean_red(&got.image, &shadowed), mean_red(&got.image, &lit));
    eprintln!(
        "{} shadowed ground pixels at {dark:.1}, {} lit at {bright:.1}",
        shadowed.len(),
        lit.len()
    );
    let ambient = f64::from(VOLUME_AMBIENT);
    let full = 255.0 * f64::from(GROUND_ALBEDO[0]) * (ambient + (1.0 - ambient) * sun.y);
    assert!(
        (bright - full).abs() < 1.5,
        "lit ground {bright}, want {full}"
    );
    assert!(
        dark < 0.75 * bright,
        "shadowed ground {dark} against lit {bright}"
    );
    assert!(got.stats.details["shadow_rays"] as usize > shadowed.len() + lit.len());
    assert_clean(&gpu);
}

/// Both ways of tracing the shell light and draw alike: with every effect on, the ray-tracing
/// pipeline's per-tet lighting, image and counters equal the compute path's exactly, from
/// outside and from inside the mesh (the secondary rays start inside it).
#[test]
fn the_ray_tracing_pipeline_lights_and_draws_as_the_compute_path() {
    let gpu = gpu();
    if !gpu.has(Need::RayTracingPipeline) {
        skip(
            "",
            &format!("{} lacks ray-tracing pipelines", gpu.caps().device_name),
        );
        return;
    }
    let compiler = shaders::compiler();
    let optics = optics(10.0);
    let size = (32, 24);
    let background = [0.1, 0.1, 0.15];
    let (_, effects) = effect_sets().pop().unwrap();
    let views = [camera(33.0, 28.0, 2.4), camera(-47.0, 12.0, 0.3)];
    // Non-convex, with a gap the secondary rays cross.
    for (name, mesh) in [("two-boxes", two_boxes())] {
        let shell = ShellMesh::build(&mesh).unwrap();
        let pixels = u64::from(size.0 * size.1);
        let draw = |path: Path, camera: &OrbitCamera| {
            let options = ShellOptions::on(LayoutKind::Tet20, path);
            let pass = Shell::with_effects(&gpu, &compiler, &options, &optics, &effects).unwrap();
            let mesh = GpuShellMesh::upload_for(&gpu, &shell, LayoutKind::Tet20, path).unwrap();
            let buffers = EffectBuffers::new(&gpu, &shell, &effects, pixels).unwrap();
            let got = pass
                .render_effects_image(
                    &gpu, &mesh, &buffers, &shell, &optics, camera, size, background,
                )
                .unwrap();
            let lighting: TetLighting = buffers.read_lighting(&gpu).unwrap();
            (got.image, got.stats, got.secondary, lighting)
        };
        for (v, camera) in views.iter().enumerate() {
            let compute = draw(Path::Compute, camera);
            let traced = draw(Path::Graphics, camera);
            let label = format!("{name} view {v}");
            assert!(
                compute.2.shadow_rays > 0 && compute.2.ao_rays > 0,
                "{label}"
            );
            assert_eq!(traced.1, compute.1, "{label}: pixel-ray counters");
            assert_eq!(traced.2, compute.2, "{label}: secondary-ray counters");
            assert!(traced.3 == compute.3, "{label}: per-tet lighting differs");
            assert_eq!(traced.0, compute.0, "{label}: images differ");
        }
    }
    assert_clean(&gpu);
}
