//! The GPU patch LOD stage of paper E against the CPU reference (`tessera_data::param::lod`):
//! the same samples at the same pixel positions and, from them, the same patches to render.

mod common;

use common::camera;
use common::param::*;
use common::{assert_clean, gpu};
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use tessera::param::{GpuParamScene, ParamPoints, ParamPointsOptions, ParamScene, View};
use tessera::shaders;
use tessera_data::param::reference::world_position;
use tessera_data::param::{run_lod, LodConfig, ParamFunction, Patch};
use tessera_data::DepthFit;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// Runs the GPU LOD stage with capture, then the CPU reference fed the captured pixel positions
/// (so transcendental functions cannot make the two differ), and demands identical outputs.
/// Returns (patches to render, steps that evaluated something, culled, limit hits).
fn assert_lod_matches(
    gpu: &Gpu,
    name: &str,
    scene: &ParamScene,
    cam: &OrbitCamera,
    options: ParamPointsOptions,
) -> (usize, usize, u32, u32) {
    let compiler = shaders::compiler();
    let points = ParamPoints::new(gpu, &compiler, options).unwrap();
    let gpu_scene = GpuParamScene::upload(gpu, scene).unwrap();
    let view = View::new(cam, SIZE, 1, DepthFit::Spheres(&gpu_scene.bounds)).unwrap();
    points.poison(gpu).unwrap();
    let capacity = 1 << 21;
    let (gpu_patches, stats, samples) = points.run_lod(gpu, &gpu_scene, &view, capacity).unwrap();
    let evaluated: u32 = stats.evaluated_per_step.iter().sum();
    assert_eq!(stats.captured, 89 * evaluated, "{name}: capture incomplete");
    assert_eq!(
        samples.len(),
        stats.captured as usize,
        "{name}: capture full"
    );
    assert_eq!(stats.dropped, 0, "{name}");

    // The GPU's pixel positions, and how far the on-screen ones are from the CPU functions'
    // projections (off screen, pixel errors grow with the distance; near the eye plane a sample
    // may fall on either side of it).
    let mut screen: HashMap<(u32, u32, u32), Vec2> = HashMap::new();
    let objects = scene.reference_objects();
    let (mut worst, mut sides) = (0.0f32, 0);
    let inside = |q: Vec2| q.cmpge(Vec2::ZERO).all() && q.cmple(view.viewport()).all();
    for s in &samples {
        let p = Vec2::new(s.x, s.y);
        let key = (s.object, s.u.to_bits(), s.v.to_bits());
        if let Some(old) = screen.insert(key, p) {
            assert!(old == p || (old.is_nan() && p.is_nan()), "{name}: {s:?}");
        }
        match view.project(world_position(&objects[s.object as usize], s.u, s.v)) {
            Some((q, _)) if !p.is_nan() && inside(q) => worst = worst.max((q - p).length()),
            Some(_) if !p.is_nan() => {}
            None if p.is_nan() => {}
            _ => sides += 1,
        }
    }
    assert!(worst < 0.05, "{name}: GPU positions {worst} pixels off");
    assert!(
        sides * 1000 <= samples.len(),
        "{name}: {sides} samples behind on one side"
    );

    let misses = AtomicUsize::new(0);
    let config = LodConfig {
        viewport: view.viewport(),
        thresholds: Vec2::from(options.thresholds),
        max_steps: options.max_steps,
        frustum_culling: options.frustum_culling,
        max_patches: options.patch_capacity as usize,
    };
    let initial: Vec<Patch> = scene
        .objects
        .iter()
        .enumerate()
        .flat_map(|(i, o)| {
            Patch::from_domain(&o.function.domain(), i as u32)
                .pre_split(options.pre_split)
                .unwrap()
        })
        .collect();
    let cpu = run_lod(
        &initial,
        |object, u, v| match screen.get(&(object, u.to_bits(), v.to_bits())) {
            Some(p) => p.extend(0.0),
            None => {
                misses.fetch_add(1, Ordering::Relaxed);
                Vec3::NAN
            }
        },
        |p| Some(p.truncate()),
        &config,
    )
    .unwrap();
    assert_eq!(misses.into_inner(), 0, "{name}: CPU samples unknown");

    let bits = |r: [f32; 2]| r.map(f32::to_bits);
    let key = |o, u, v, e, step, over: bool| (o, bits(u), bits(v), bits(e), step, over);
    let mut g: Vec<_> = gpu_patches
        .iter()
        .map(|p| key(p.object, p.u, p.v, p.extent, p.step(), p.over_threshold()))
        .collect();
    let mut c: Vec<_> = (cpu.render.iter())
        .map(|r| (r.patch, r.extent.to_array(), r.step, r.over_threshold))
        .map(|(p, e, step, over)| key(p.object, p.u, p.v, e, step, over))
        .collect();
    g.sort();
    c.sort();
    assert_eq!(g.len(), c.len(), "{name}: patch counts differ");
    assert!(g == c, "{name}: the patches to render differ");
    let cpu_steps: Vec<u32> = cpu.evaluated_per_step.iter().map(|&n| n as u32).collect();
    assert_eq!(stats.evaluated_per_step, cpu_steps, "{name}");
    assert_eq!(stats.culled as usize, cpu.culled, "{name}");
    assert_eq!(stats.limit_hits as usize, cpu.limit_hits, "{name}");
    let hits = stats.resolution_hits as usize;
    assert_eq!(hits, cpu.resolution_hits, "{name}");
    let steps = cpu_steps.iter().filter(|&&n| n > 0).count();
    eprintln!(
        "{name}: {} patches to render, {steps} steps, evaluated {cpu_steps:?}, {} culled, \
         {} limit hits, positions within {worst:.1e} px",
        g.len(),
        stats.culled,
        stats.limit_hits
    );
    (g.len(), steps, stats.culled, stats.limit_hits)
}

#[test]
fn lod_matches_the_cpu() {
    let gpu = gpu();
    let sphere = || one(ParamFunction::Sphere);
    // (name, scene, camera, threshold, steps, least patches, least steps, culls, hits limit)
    #[rustfmt::skip]
    let cases = [
        ("sphere", sphere(), camera(30.0, 20.0, 3.5), 84.0, 12, 5, 3, false, false),
        ("sphere close", sphere(), camera(10.0, 35.0, 1.6), 12.0, 12, 500, 6, true, false),
        ("heart", one(ParamFunction::Heart), camera(-40.0, 10.0, 2.5), 10.0, 12, 200, 6, false, false),
        ("glyph", one(glyph8()), camera(60.0, -25.0, 2.2), 16.0, 12, 200, 6, true, false),
        ("trio", trio(), camera(25.0, 5.0, 1.2), 20.0, 12, 200, 6, true, false),
        ("step limit", sphere(), camera(0.0, 0.0, 3.0), 4.0, 3, 50, 3, false, true),
    ];
    for (name, scene, cam, t, max_steps, patches, steps, culls, limit) in cases {
        let options = points_opts!(thresholds: [t, t], max_steps: max_steps);
        let (n, s, culled, hits) = assert_lod_matches(&gpu, name, &scene, &cam, options);
        assert!(n >= patches && s >= steps, "{name}: {n} patches, {s} steps");
        assert_eq!((culled > 0, hits > 0), (culls, limit), "{name}");
    }
    assert_clean(&gpu);
}

#[test]
fn pre_split_lod_matches_the_cpu() {
    let gpu = gpu();
    let options = points_opts!(thresholds: [20.0, 20.0], pre_split: 4);
    let (n, _, _, _) = assert_lod_matches(
        &gpu,
        "trio pre-split",
        &trio(),
        &camera(25.0, 5.0, 1.2),
        options,
    );
    assert!(n >= 3 * 16, "{n} patches: every object starts as 16");
    let compiler = shaders::compiler();
    for bad in [0, 3, 32] {
        assert!(
            ParamPoints::new(&gpu, &compiler, points_opts!(pre_split: bad)).is_err(),
            "{bad}"
        );
    }
    assert_clean(&gpu);
}

/// Small glyphs keep their thin lobes: an 8×8 field of order-8 glyphs at 256² by points and by
/// tessellation covers what the ray tracer covers (IoU ≥ 0.98). Drawn with the LOD's measured
/// extents alone, lobes between its sample lines were lost (IoU 0.62 points, 0.64
/// tessellation); the glyphs' bounding spheres now bound the extents from below
/// (`param/min_extent.glsl`), and tessellation starts glyphs as 2 × 2 patches, since one patch
/// gets at most 64 segments per edge (0.968 from whole glyphs).
#[test]
fn default_lod_keeps_thin_lobes_of_small_glyphs() {
    use tessera::renderer::{self, RendererOptions, Technique};
    use tessera_data::scene::{Appearance, Dataset, LoadOptions};
    let gpu = gpu();
    let data = Dataset::load("param:sh-glyphs:8x8:order8", &LoadOptions::default()).unwrap();
    let look = Appearance {
        background: Some(BACKGROUND),
        ..Appearance::default()
    };
    let render = |technique| {
        let mut r = renderer::create(&gpu, technique, &RendererOptions::default()).unwrap();
        r.set_appearance(&gpu, &look).unwrap();
        r.set_data(&gpu, &data).unwrap();
        renderer::render_image(&gpu, r.as_mut(), &camera(0.0, 0.0, 1.2), (256, 256))
            .unwrap()
            .image
    };
    let traced = render(Technique::ShRaytrace);
    for (technique, least) in [(Technique::ParamPoints, 0.98), (Technique::ParamTess, 0.98)] {
        let (iou, _, _) = compare(&render(technique), &traced);
        assert!(iou >= least, "{}: IoU {iou}", technique.name());
    }
    assert_clean(&gpu);
}
