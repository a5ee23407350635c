//! `param-tess` (paper E's TESSELLATION-BASED variant) against the CPU reference images of
//! `tessera_data::param::reference`, against `param-points`, and its options and counts.

mod common;

use common::camera;
use common::param::*;

use common::{assert_clean, gpu, out_dir, skip, write_png};
use glam::Vec3;
use std::collections::{BTreeMap, BTreeSet};
use tessera::param::tess::{ParamTess, ParamTessOptions, TessFrame, TessLevels};
use tessera::param::{GpuParamScene, ParamPoints, ParamScene, View};
use tessera::shaders;
use tessera::target::Target;
use tessera_data::param::reference::{
    reference_fragments, render_reference, shade_point, ReferenceView, DEFAULT_MAX_CELL_PX,
};
use tessera_data::param::ParamFunction;
use tessera_data::shading::pack_rgba8;
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::pipeline::sample_count_flag;
use tessera_gpu::Gpu;

macro_rules! opts {
    ($($field:ident: $value:expr),*) => {
        ParamTessOptions { $($field: $value,)* ..ParamTessOptions::default() }
    };
}

const FIXED: TessLevels = TessLevels::Fixed(24);

// ---------------------------------------------------------------------------------------------
// Images

/// What [`render`] made.
struct Rendered {
    image: RgbaImage,
    view: View,
    /// Patches the draw drew.
    patches: u32,
    /// Instances of the draw.
    instances: u32,
    gpu_ms: f64,
}

/// Renders `scene` with poisoned outputs and checks the frame's counts: every pixel written,
/// the indirect draw drew exactly the patches the LOD stage listed.
fn render(gpu: &Gpu, scene: &ParamScene, cam: &OrbitCamera, options: ParamTessOptions) -> Rendered {
    let compiler = shaders::compiler();
    let tess = ParamTess::new(gpu, &compiler, options).unwrap();
    let gpu_scene = GpuParamScene::upload(gpu, scene).unwrap();
    let view = tess.view(&gpu_scene, cam, SIZE).unwrap();
    let frame = tess.frame(gpu, &view).unwrap();
    let pixels = Target::new(gpu, SIZE.0, SIZE.1).unwrap();
    pixels.poison(gpu, POISON).unwrap();
    tess.poison(gpu).unwrap();
    let info = tess
        .render_frame(gpu, &gpu_scene, &view, &frame, &pixels, BACKGROUND)
        .unwrap();
    let image = pixels.read(gpu).unwrap();
    let args = tess.read_draw_args(gpu).unwrap();
    let per = tess.patches_per_instance();
    assert!(!image.pixels.contains(&POISON), "pixels never written");
    let rendered = info.stats.rendered;
    assert!(rendered > 0 && info.stats.dropped == 0, "{:?}", info.stats);
    let instances = rendered.div_ceil(per);
    assert_eq!(
        args,
        [rendered.min(per), instances, 0, 0],
        "indirect draw arguments, {per} patches per instance"
    );
    eprintln!(
        "{rendered} patches in {instances} instance(s), GPU {:.1} ms",
        info.gpu_ms
    );
    Rendered {
        image,
        view,
        patches: rendered,
        instances,
        gpu_ms: info.gpu_ms,
    }
}

/// Holds `image` to `reference`: silhouette IoU >= `min_iou`, >= 98 % of the pixels both cover
/// within 4/255, enough surface in view. Writes PNGs when it fails (or TESSERA_KEEP_IMAGES).
fn assert_matches(name: &str, image: &RgbaImage, reference: &RgbaImage, min_iou: f64) {
    let (iou, within, covered) = compare(image, reference);
    eprintln!(
        "{name}: IoU {iou:.4}, {:.2}% of {covered} co-covered pixels within 4/255",
        within * 100.0
    );
    let failed = iou < min_iou || within < 0.98 || covered < (SIZE.0 * SIZE.1 / 10) as usize;
    if failed || std::env::var_os("TESSERA_KEEP_IMAGES").is_some() {
        let dir = out_dir();
        write_png(&dir.join(format!("tess-{name}-actual.png")), image);
        write_png(&dir.join(format!("tess-{name}-expected.png")), reference);
        write_png(
            &dir.join(format!("tess-{name}-diff.png")),
            &image.diff_image(reference),
        );
    }
    assert!(
        !failed,
        "{name}: IoU {iou}, within {within}, covered {covered}; images in {}",
        out_dir().display()
    );
}

fn reference(scene: &ParamScene, view: &ReferenceView) -> RgbaImage {
    let objects = scene.reference_objects();
    render_reference(&objects, view, BACKGROUND, DEFAULT_MAX_CELL_PX).unwrap()
}

/// Renders with adaptive and with fixed levels and holds both to the reference.
fn assert_both_levels_match(gpu: &Gpu, name: &str, scene: &ParamScene, cam: &OrbitCamera) {
    let mut images = Vec::new();
    for (kind, levels) in [("adaptive", opts!().levels), ("fixed", FIXED)] {
        eprint!("{name} {kind}: ");
        let r = render(gpu, scene, cam, opts!(levels: levels));
        let expected = reference(scene, &r.view.reference());
        assert_matches(&format!("{name}-{kind}"), &r.image, &expected, 0.99);
        images.push(r.image);
    }
    // The two level rules tessellate differently, so equal images would mean the levels were
    // ignored (24 segments per patch against up to 64 move silhouettes by a pixel here and
    // there).
    assert!(
        images[0] != images[1],
        "{name}: the level rule changed nothing"
    );
}

#[test]
fn sphere_matches_the_reference() {
    let gpu = gpu();
    let scene = one(ParamFunction::Sphere);
    let cam = camera(30.0, 20.0, 3.5);
    assert_both_levels_match(&gpu, "sphere", &scene, &cam);
    // The clamp: adaptive levels held to [24, 24] are the fixed level 24 exactly.
    let TessLevels::Fixed(l) = FIXED else {
        unreachable!()
    };
    let clamped = render(&gpu, &scene, &cam, opts!(min_level: l, max_level: l));
    let fixed = render(&gpu, &scene, &cam, opts!(levels: FIXED));
    assert!(clamped.image == fixed.image, "clamped adaptive levels");
    assert_clean(&gpu);
}

#[test]
fn heart_matches_the_reference() {
    let gpu = gpu();
    let scene = one(ParamFunction::Heart);
    assert_both_levels_match(&gpu, "heart", &scene, &camera(-30.0, 15.0, 2.6));
    assert_clean(&gpu);
}

#[test]
fn glyph_matches_the_reference() {
    let gpu = gpu();
    let scene = one(glyph8());
    assert_both_levels_match(&gpu, "glyph", &scene, &camera(60.0, -25.0, 2.4));
    assert_clean(&gpu);
}

/// The adaptive rule read back through the debug colouring: the inner levels of every drawn
/// patch are `clamp(ceil(e / p), min, max)` of the extents the LOD stage measured for it.
#[test]
fn adaptive_levels_follow_the_extents() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    // p = 2 divides exactly, so the GPU's ceil sees the CPU's quotient.
    let (p, lo, hi) = (2.0f32, 14, 24);
    let levels = TessLevels::Adaptive {
        pixels_per_segment: p,
    };
    let options = opts!(levels: levels, min_level: lo, max_level: hi, debug_levels: true);
    let tess = ParamTess::new(&gpu, &compiler, options).unwrap();
    let scene = GpuParamScene::upload(&gpu, &one(glyph8())).unwrap();
    tess.poison(&gpu).unwrap();
    let cam = camera(60.0, -25.0, 2.4);
    let (image, _) = tess
        .render_image(&gpu, &scene, &cam, SIZE, [0.0; 3])
        .unwrap();
    let patches = tess.read_patches(&gpu).unwrap();
    let level = |e: f32| (e / p).ceil().clamp(lo as f32, hi as f32) as u32;
    let expected: BTreeSet<(u32, u32)> = patches
        .iter()
        .map(|q| (level(q.extent[0]), level(q.extent[1])))
        .collect();
    let mut observed: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for &px in image.pixels.iter().filter(|&&px| px & 0xff_ffff != 0) {
        *observed.entry((px & 0xff, (px >> 8) & 0xff)).or_default() += 1;
    }
    eprintln!(
        "{} patches, level pairs expected {expected:?}, seen (pixels) {observed:?}",
        patches.len()
    );
    assert!(observed.keys().all(|k| expected.contains(k)));
    // Enough variety that a wrong rule would show: clamped at both ends and in between.
    let seen: BTreeSet<u32> = observed.keys().flat_map(|&(a, b)| [a, b]).collect();
    assert!(seen.contains(&lo) && seen.contains(&hi), "{seen:?}");
    assert!(seen.iter().any(|l| (lo + 1..hi).contains(l)), "{seen:?}");
    assert_clean(&gpu);
}

/// Vulkan's standard sample positions in sixteenths of a pixel: each lies at the centre of a
/// cell of an `n × n` grid, which is where a reference supersampled `n` times samples.
fn standard_positions(samples: u32) -> &'static [(u32, u32)] {
    match samples {
        2 => &[(12, 12), (4, 4)],
        4 => &[(6, 2), (14, 6), (2, 10), (10, 14)],
        8 => &[
            (9, 5),
            (7, 11),
            (13, 9),
            (5, 3),
            (3, 13),
            (1, 7),
            (11, 15),
            (15, 1),
        ],
        _ => panic!("no standard positions for {samples} samples"),
    }
}

/// The reference of an `n`-sample MSAA image: each pixel the average of the shaded reference
/// samples at the standard positions (taken from a reference raster `n` times as fine).
fn msaa_reference(scene: &ParamScene, view: &View, samples: u32) -> RgbaImage {
    let objects = scene.reference_objects();
    let fine = ReferenceView {
        supersample: samples,
        ..view.reference()
    };
    let frags = reference_fragments(&objects, &fine, DEFAULT_MAX_CELL_PX).unwrap();
    let (w, h) = view.size;
    let width = w * samples;
    let pixels = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let mut sum = Vec3::ZERO;
            for &(px, py) in standard_positions(samples) {
                let (sx, sy) = (px * samples / 16, py * samples / 16);
                let f = frags[((y * samples + sy) * width + x * samples + sx) as usize];
                sum += match f {
                    Some(f) => shade_point(&objects[f.object as usize], f.u, f.v, &fine),
                    None => Vec3::from(BACKGROUND),
                };
            }
            let c = sum / standard_positions(samples).len() as f32;
            pack_rgba8([c.x, c.y, c.z, 1.0])
        })
        .collect();
    RgbaImage {
        width: w,
        height: h,
        pixels,
    }
}

/// MSAA (4 samples, and 2 and 8 where the device has them) against the reference sampled at
/// the standard positions, and 2x2 supersampling against the reference supersampled alike.
#[test]
fn msaa_and_supersampling_match_the_reference() {
    let gpu = gpu();
    let scene = one(glyph8());
    let cam = camera(-50.0, 30.0, 2.4);
    let counts = gpu.attachment_sample_counts();
    let mut tried = 0;
    for samples in [2, 4, 8] {
        if !counts.contains(sample_count_flag(samples).unwrap()) {
            assert_ne!(samples, 4, "every Vulkan device has 4-sample attachments");
            skip(
                &format!("MSAA {samples}"),
                "no such attachments on this device",
            );
            continue;
        }
        eprint!("MSAA {samples}: ");
        let r = render(&gpu, &scene, &cam, opts!(msaa: samples));
        let expected = msaa_reference(&scene, &r.view, samples);
        assert_matches(&format!("msaa{samples}"), &r.image, &expected, 0.99);
        // Edges are blended: the image holds colours that no single sample has.
        let single = reference(&scene, &r.view.reference());
        assert!(
            compare(&r.image, &single).1 < 1.0,
            "MSAA {samples}: no blended edges"
        );
        tried += 1;
    }
    assert!(tried >= 1);
    eprint!("supersampled 2x2: ");
    let r = render(&gpu, &scene, &cam, opts!(supersample: 2));
    assert_eq!(r.view.raster_size(), (2 * SIZE.0, 2 * SIZE.1));
    let expected = reference(&scene, &r.view.reference());
    assert_matches("ss2", &r.image, &expected, 0.99);
    // This frame's evaluation stage makes far more than 65,536 vertices: on lavapipe it is drawn
    // in several instances, without which its triangles would join the wrong vertices.
    assert!(r.patches > 64, "{} patches", r.patches);
    if gpu.caps().is_cpu() {
        assert!(r.instances > 1, "one instance of {} patches", r.patches);
    }
    assert_clean(&gpu);
}

/// The two variants of paper E draw the same silhouettes from the same LOD stage.
#[test]
fn tess_and_points_agree() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let scene = trio();
    let cam = camera(25.0, 10.0, 3.2);
    eprint!("trio: ");
    let tess = render(&gpu, &scene, &cam, opts!());
    let points = ParamPoints::new(&gpu, &compiler, Default::default()).unwrap();
    let gpu_scene = GpuParamScene::upload(&gpu, &scene).unwrap();
    let (points_image, points_ms) = points
        .render_image(&gpu, &gpu_scene, &cam, SIZE, BACKGROUND)
        .unwrap();
    eprintln!("trio: points GPU {points_ms:.1} ms");
    assert!(tess.gpu_ms > 0.0);
    assert_matches("vs-points", &tess.image, &points_image, 0.99);
    assert_clean(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn bad_options_are_refused() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let max = gpu.caps().max_tessellation_level;
    let adaptive = |p: f32| TessLevels::Adaptive {
        pixels_per_segment: p,
    };
    let mut bad = vec![
        opts!(levels: TessLevels::Fixed(0)),
        opts!(levels: TessLevels::Fixed(max + 1)),
        opts!(levels: adaptive(0.0)),
        opts!(levels: adaptive(f32::NAN)),
        opts!(min_level: 0),
        opts!(min_level: 16, max_level: 8),
        opts!(max_level: max + 1),
        opts!(msaa: 0),
        opts!(msaa: 3),
        opts!(msaa: 16),
        opts!(supersample: 0),
        opts!(supersample: 9),
        opts!(max_steps: 0),
        opts!(patch_capacity: 0),
    ];
    let counts = gpu.attachment_sample_counts();
    let unsupported: Vec<u32> = [2, 8]
        .into_iter()
        .filter(|&n| !counts.contains(sample_count_flag(n).unwrap()))
        .collect();
    eprintln!("MSAA counts the device lacks: {unsupported:?}");
    bad.extend(unsupported.iter().map(|&n| opts!(msaa: n)));
    for options in bad {
        let err = ParamTess::new(&gpu, &compiler, options).err();
        assert!(err.is_some(), "{options:?} accepted");
        eprintln!("{options:?}: {}", err.unwrap());
    }

    // The limits themselves are accepted.
    let edge = opts!(levels: TessLevels::Fixed(max), min_level: 1, max_level: max);
    ParamTess::new(&gpu, &compiler, edge).unwrap();

    // Lists of 8 patches cannot hold a close sphere's LOD: the frame is refused, not drawn.
    let tess = ParamTess::new(&gpu, &compiler, opts!(patch_capacity: 8)).unwrap();
    let scene = GpuParamScene::upload(&gpu, &one(ParamFunction::Sphere)).unwrap();
    let cam = camera(0.0, 0.0, 2.0);
    for size in [SIZE, (0, 10)] {
        assert!(tess
            .render_image(&gpu, &scene, &cam, size, BACKGROUND)
            .is_err());
    }
    // A frame made for another view is refused.
    let view = tess.view(&scene, &cam, SIZE).unwrap();
    let other = tess.view(&scene, &cam, (SIZE.0 / 2, SIZE.1)).unwrap();
    let frame = tess.frame(&gpu, &other).unwrap();
    let pixels = Target::new(&gpu, SIZE.0, SIZE.1).unwrap();
    let other_pixels = Target::new(&gpu, SIZE.0 / 2, SIZE.1).unwrap();
    assert!(tess
        .render_frame(&gpu, &scene, &view, &frame, &pixels, BACKGROUND)
        .is_err());
    assert!(
        tess.render_frame(
            &gpu,
            &scene,
            &view,
            &tess.frame(&gpu, &view).unwrap(),
            &other_pixels,
            BACKGROUND
        )
        .is_err(),
        "an image of another size is refused"
    );
    let msaa4 = TessFrame::new(&gpu, &view, 4).unwrap();
    assert!(tess
        .render_frame(&gpu, &scene, &view, &msaa4, &pixels, BACKGROUND)
        .is_err());
    assert_clean(&gpu);
}
