//! `sh-raytrace` (Peters et al. 2023, paper E's comparison) against the CPU: images against the
//! tessellated reference of `tessera_data::param::reference` and against param-points, hit
//! points against the glyphs' own radius function and the f64 ray tracer of
//! `tessera_data::param::raytrace`, traversal independent of the grid, bad input refused.

mod common;

use common::camera;
use common::param::*;

use common::{assert_clean, gpu, out_dir, write_png};
use glam::{DVec3, Mat4, Quat, Vec3};
use tessera::param::raytrace::{camera_rays, RayHit, ShRaytrace, ShRaytraceOptions};
use tessera::param::{GpuParamScene, ParamObject, ParamPoints, ParamPointsOptions, ParamScene};
use tessera::shaders;
use tessera::target::Target;
use tessera_data::image::coverage_of;
use tessera_data::param::raytrace::{glyph_bound, radius_scale_offset, trace_glyphs, GlyphGrid};
use tessera_data::param::reference::{render_reference, DEFAULT_MAX_CELL_PX};
use tessera_data::param::sh::sh_coefficient_count;
use tessera_data::param::{ParamFunction, RadiusNormalization, ShBasis, ShGlyph};
use tessera_data::shading::pack_rgba8;
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::Gpu;

const NON_LEGACY: ShBasis = ShBasis::Descoteaux07 { legacy: false };

fn opts(max_order: u32, supersample: u32, cell_scale: f32) -> ShRaytraceOptions {
    ShRaytraceOptions {
        max_order,
        supersample,
        cell_scale,
    }
}

/// A glyph of `order` with deterministic pseudo-random coefficients shrinking as `1/√l` around
/// an `l = 0` term.
fn lobed(order: u32, seed: u32, basis: ShBasis, norm: RadiusNormalization) -> ParamFunction {
    let n = sh_coefficient_count(order).unwrap();
    let mut rng = common::Rng::new(u64::from(seed));
    let mut next = move || rng.range(-0.5, 0.5);
    let degrees = tessera_data::param::sh::sh_degrees_and_orders(order).unwrap();
    // Positive-lobe glyphs get a small constant term, so that they have negative lobes to drop.
    let dc = if norm == RadiusNormalization::PositiveLobes {
        0.15
    } else {
        1.2
    };
    let c = (0..n)
        .map(|j| match degrees[j].0 {
            0 => dc,
            l => next() * 1.6 / f64::from(l).sqrt(),
        })
        .collect();
    ParamFunction::ShGlyph(ShGlyph::new(basis, order, c, norm).unwrap())
}

/// A 4×4 field of glyphs of orders 2…12 in all bases, turned and scaled non-uniformly: min-max
/// normalised but for one raw, one max-abs and one positive-lobes glyph, and an order-0
/// (min-max: unit sphere) one.
fn field() -> ParamScene {
    let bases = [
        NON_LEGACY,
        ShBasis::Descoteaux07 { legacy: true },
        ShBasis::Tournier07 { legacy: false },
        ShBasis::Tournier07 { legacy: true },
    ];
    let objects = (0..16u32)
        .map(|i| {
            let order = if i == 15 { 0 } else { 2 + 2 * (i % 6) };
            let norm = match i {
                5 => RadiusNormalization::MaxAbs,
                7 => RadiusNormalization::PositiveLobes,
                10 => RadiusNormalization::Raw,
                _ => RadiusNormalization::MinMax,
            };
            let f = lobed(order, i, bases[i as usize % 4], norm);
            let scale = if i == 10 { 0.16 } else { 0.32 };
            let at = Vec3::new((i % 4) as f32 - 1.5, (i / 4) as f32 - 1.5, 0.0) * 0.62;
            let turn = Quat::from_euler(glam::EulerRot::XYZ, 0.3 * i as f32, 0.7, 0.2 * i as f32);
            let scaling = Vec3::new(scale, scale * 0.9, scale * 1.1);
            ParamObject::new(f)
                .with_transform(Mat4::from_scale_rotation_translation(scaling, turn, at))
        })
        .collect();
    ParamScene::new(objects)
}

// ---------------------------------------------------------------------------------------------
// Images

/// `scene` ray traced into a poisoned target: the image, its view and the GPU milliseconds.
fn raytrace(
    gpu: &Gpu,
    scene: &ParamScene,
    cam: &OrbitCamera,
    options: ShRaytraceOptions,
) -> (RgbaImage, tessera_data::View, f64) {
    let rt = ShRaytrace::new(gpu, &shaders::compiler(), options).unwrap();
    let prepared = rt.prepare(gpu, scene).unwrap();
    let view = rt.view(&prepared, cam, SIZE).unwrap();
    let target = Target::new(gpu, SIZE.0, SIZE.1).unwrap();
    target.poison(gpu, POISON).unwrap();
    let ms = rt
        .render_into(gpu, &prepared, &view, &target, BACKGROUND)
        .unwrap();
    let image = target.read(gpu).unwrap();
    assert!(!image.pixels.contains(&POISON), "pixels never written");
    (image, view, ms)
}

fn param_points(gpu: &Gpu, scene: &ParamScene, cam: &OrbitCamera, supersample: u32) -> RgbaImage {
    let options = ParamPointsOptions {
        supersample,
        // At its default one sample per pixel, param-points' cells are too coarse for the
        // field's spiky order-10 and 12 glyphs of ~20 pixels: 91 % of pixels within 4/255 of
        // the CPU reference there, 99.5 % at four.
        density: 4.0,
        ..ParamPointsOptions::default()
    };
    let points = ParamPoints::new(gpu, &shaders::compiler(), options).unwrap();
    let uploaded = GpuParamScene::upload(gpu, scene).unwrap();
    let (image, _) = points
        .render_image(gpu, &uploaded, cam, SIZE, BACKGROUND)
        .unwrap();
    image
}

/// Silhouette IoU >= 0.99 and >= 98 % of co-covered pixels within 4/255, with enough surface
/// in view; PNGs of both and their difference when not.
fn assert_close(name: &str, image: &RgbaImage, expected: &RgbaImage) {
    let (iou, within, covered) = compare(image, expected);
    eprintln!(
        "{name}: IoU {iou:.4}, {:.2}% of co-covered pixels within 4/255, {covered} covered",
        within * 100.0
    );
    let keep = std::env::var_os("TESSERA_KEEP_IMAGES").is_some();
    let (w, h) = SIZE;
    let failed = iou < 0.99 || within < 0.98 || covered < (w * h / 10) as usize;
    if keep || failed {
        let dir = out_dir();
        write_png(&dir.join(format!("{name}-actual.png")), image);
        write_png(&dir.join(format!("{name}-expected.png")), expected);
        write_png(
            &dir.join(format!("{name}-diff.png")),
            &image.diff_image(expected),
        );
    }
    assert!(
        !failed,
        "{name}: IoU {iou}, within {within}, covered {covered}; images in {}",
        out_dir().display()
    );
}

/// Ray traces `scene` and holds it to the CPU reference and to param-points.
fn assert_scene_matches(gpu: &Gpu, name: &str, scene: &ParamScene, cam: &OrbitCamera, ss: u32) {
    let (image, view, ms) = raytrace(gpu, scene, cam, opts(12, ss, 1.0));
    eprintln!("{name}: sh-raytrace GPU {ms:.1} ms");
    let objects = scene.reference_objects();
    let reference =
        render_reference(&objects, &view.reference(), BACKGROUND, DEFAULT_MAX_CELL_PX).unwrap();
    assert_close(&format!("rt-{name}-vs-reference"), &image, &reference);
    let points = param_points(gpu, scene, cam, ss);
    let (iou, within, _) = compare(&points, &reference);
    eprintln!(
        "{name}: param-points vs reference: IoU {iou:.4}, {:.2}% within",
        within * 100.0
    );
    assert_close(&format!("rt-{name}-vs-points"), &image, &points);
}

#[test]
fn one_glyph_matches_the_reference_and_param_points() {
    let gpu = gpu();
    let scene = ParamScene::new(vec![ParamObject::new(glyph8())]);
    assert_scene_matches(&gpu, "glyph8", &scene, &camera(60.0, -25.0, 2.4), 1);
    assert_scene_matches(&gpu, "glyph8-ss2", &scene, &camera(-20.0, 40.0, 2.6), 2);
    assert_clean(&gpu);
}

#[test]
fn glyph_field_matches_the_reference_and_param_points() {
    let gpu = gpu();
    assert_scene_matches(&gpu, "field", &field(), &camera(15.0, 50.0, 3.4), 1);
    assert_clean(&gpu);
}

/// Orders 14 and 16, above Peters et al.'s 12, in shaders built for 16.
#[test]
fn high_orders_match_the_reference() {
    let gpu = gpu();
    let scene = ParamScene::new(vec![
        ParamObject::new(lobed(14, 3, NON_LEGACY, RadiusNormalization::MinMax)).with_transform(
            Mat4::from_translation(Vec3::new(-0.55, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.5)),
        ),
        ParamObject::new(lobed(16, 4, NON_LEGACY, RadiusNormalization::MinMax)).with_transform(
            Mat4::from_translation(Vec3::new(0.55, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.5)),
        ),
    ]);
    let cam = camera(35.0, 20.0, 3.2);
    let (image, view, ms) = raytrace(&gpu, &scene, &cam, opts(16, 1, 1.0));
    eprintln!("orders 14 and 16: sh-raytrace GPU {ms:.1} ms");
    let reference = render_reference(
        &scene.reference_objects(),
        &view.reference(),
        BACKGROUND,
        DEFAULT_MAX_CELL_PX,
    )
    .unwrap();
    assert_close("rt-order16-vs-reference", &image, &reference);
    assert_clean(&gpu);
}

/// The grid only decides which glyphs a ray meets when: one cell, cells of a glyph's size and
/// cells of a third of it give the same image (up to where each root search stops).
#[test]
fn images_do_not_depend_on_the_grid() {
    let gpu = gpu();
    let scene = field();
    let cam = camera(-30.0, 60.0, 3.4);
    let (fine, _, fine_ms) = raytrace(&gpu, &scene, &cam, opts(12, 1, 0.3));
    let (one, _, one_ms) = raytrace(&gpu, &scene, &cam, opts(12, 1, 1e6));
    let (normal, _, ms) = raytrace(&gpu, &scene, &cam, opts(12, 1, 1.0));
    eprintln!("GPU ms: cells of 0.3 glyphs {fine_ms:.1}, one cell {one_ms:.1}, 1 glyph {ms:.1}");
    for (name, other) in [("fine", &fine), ("single", &one)] {
        let diff = normal.compare(other, 1);
        assert!(
            diff.fraction_within >= 0.999,
            "{name}: {} pixels differ by more than 1/255",
            diff.pixels_outside
        );
    }
    assert_clean(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Hit points

/// The camera ray through raster position `p` (origin, unit direction) in f64, from the view's
/// own matrix as the shaders get it.
fn cpu_ray(view: &tessera_data::View, p: [f32; 2]) -> (Vec3, Vec3) {
    let (w, h) = view.raster_size();
    let ndc = DVec3::new(
        f64::from(p[0]) / f64::from(w) * 2.0 - 1.0,
        f64::from(p[1]) / f64::from(h) * 2.0 - 1.0,
        1.0,
    );
    let (centre, rays) = camera_rays(view);
    (centre.as_vec3(), (rays * ndc).normalize().as_vec3())
}

/// Hit points read back from the probe pass lie on the glyph they name (the glyph's radius
/// function in f64), agree with the CPU ray tracer's first hit, and carry the reference's
/// normals.
#[test]
fn hits_lie_on_the_glyph_surfaces() {
    let gpu = gpu();
    let scene = field();
    let rt = ShRaytrace::new(&gpu, &shaders::compiler(), opts(12, 1, 1.0)).unwrap();
    let prepared = rt.prepare(&gpu, &scene).unwrap();
    let view = rt.view(&prepared, &camera(15.0, 50.0, 3.4), SIZE).unwrap();
    // A grid of pixel centres, and rays through the glyph centres, where F has a 2k-fold root.
    let mut raster: Vec<[f32; 2]> = (0..SIZE.1)
        .step_by(3)
        .flat_map(|y| {
            (0..SIZE.0)
                .step_by(3)
                .map(move |x| [x as f32 + 0.5, y as f32 + 0.5])
        })
        .collect();
    let centres = scene
        .objects
        .iter()
        .map(|o| o.object_to_world.w_axis.truncate());
    raster.extend(
        centres
            .filter_map(|c| view.project(c))
            .map(|p| p.0.to_array()),
    );
    let hits = rt.probe(&gpu, &prepared, &view, &raster).unwrap();
    assert_eq!(hits.len(), raster.len());
    let objects = scene.reference_objects();
    let grid = GlyphGrid::build(&scene.bounding_spheres(), 1.0).unwrap();
    let (mut on_surface, mut worst, mut worst_t) = (0, 0.0f64, 0.0f64);
    let (mut unlike, mut normals_off, mut hit_count) = (0, 0, 0);
    for (p, hit) in raster.iter().zip(&hits) {
        assert!(
            hit.glyph == RayHit::NONE || (hit.glyph as usize) < objects.len(),
            "{p:?}: never written ({:#x})",
            hit.glyph
        );
        let (eye, dir) = cpu_ray(&view, *p);
        let cpu = trace_glyphs(&objects, &grid, eye, dir);
        if cpu.map(|c| c.0) != (hit.glyph != RayHit::NONE).then_some(hit.glyph) {
            unlike += 1;
            continue;
        }
        let Some((index, t)) = cpu else { continue };
        hit_count += 1;
        let ParamFunction::ShGlyph(g) = objects[index as usize].function else {
            unreachable!()
        };
        let position = Vec3::from_slice(&hit.position[..3]);
        worst_t = worst_t.max((f64::from(hit.position[3]) - t).abs());
        assert!(
            (eye + dir * hit.position[3] - position).length() < 1e-5,
            "{p:?}"
        );
        // The object-space point against the glyph's radius there.
        let m = objects[index as usize].object_to_world.as_dmat4();
        let q = m.inverse().transform_point3(position.as_dvec3());
        let (theta, phi) = (q.x.hypot(q.y).atan2(q.z), q.y.atan2(q.x));
        let (s, o) = radius_scale_offset(g);
        let value = g.raw_radius(theta, phi) * s + o;
        let drawn = if g.normalization() == RadiusNormalization::PositiveLobes {
            value.max(0.0)
        } else {
            value.abs()
        };
        let radius = drawn.min(glyph_bound(g));
        let residual = (q.length() - radius).abs() / glyph_bound(g);
        worst = worst.max(residual);
        on_surface += usize::from(residual < 2e-4);
        // The reference's normal at the same direction (any orientation).
        let phi = if phi < 0.0 {
            phi + std::f64::consts::TAU
        } else {
            phi
        };
        let n = tessera_data::param::reference::world_normal(
            &objects[index as usize],
            theta as f32,
            phi as f32,
        );
        let got = Vec3::from_slice(&hit.normal[..3]);
        if n.is_none_or(|n| n.dot(got).abs() < 0.999) {
            normals_off += 1;
        }
        // Colour by direction from the glyph centre, in object space.
        let colour = q.normalize().abs().as_vec3();
        assert!(
            (Vec3::from_slice(&hit.colour[..3]) - colour).length() < 1e-3,
            "{p:?}"
        );
    }
    eprintln!(
        "{hit_count} hits: {on_surface} within 2e-4 B of the surface (worst {worst:.1e} B), \
         t within {worst_t:.1e} of the CPU's, {unlike} of {} rays unlike the CPU's, \
         {normals_off} normals off the reference's",
        raster.len()
    );
    assert!(
        worst_t < 1e-4,
        "t differs from the CPU's by up to {worst_t}"
    );
    assert!(hit_count > raster.len() / 5, "{hit_count} hits");
    assert_eq!(on_surface, hit_count, "worst residual {worst:e} B");
    assert!(
        unlike * 200 <= raster.len(),
        "{unlike} rays hit another glyph than on the CPU"
    );
    assert!(
        normals_off * 50 <= hit_count,
        "{normals_off} normals differ"
    );
    assert_clean(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn bad_input_is_refused() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    for bad in [
        opts(18, 1, 1.0),
        opts(7, 1, 1.0),
        opts(12, 0, 1.0),
        opts(12, 9, 1.0),
        opts(12, 1, 0.0),
        opts(12, 1, f32::NAN),
    ] {
        assert!(ShRaytrace::new(&gpu, &compiler, bad).is_err(), "{bad:?}");
    }
    let rt = ShRaytrace::new(&gpu, &compiler, ShRaytraceOptions::default()).unwrap();
    let mixed = ParamScene::new(vec![
        ParamObject::new(glyph8()),
        ParamObject::new(ParamFunction::Sphere),
    ]);
    let message = rt.prepare(&gpu, &mixed).err().unwrap().to_string();
    assert!(
        message.contains("SH glyphs only") && message.contains("object 1"),
        "{message}"
    );
    let high = ParamScene::new(vec![ParamObject::new(lobed(
        14,
        1,
        NON_LEGACY,
        RadiusNormalization::MinMax,
    ))]);
    let message = rt.prepare(&gpu, &high).err().unwrap().to_string();
    assert!(message.contains("max_order"), "{message}");
    assert!(rt.prepare(&gpu, &ParamScene::default()).is_err());
    // A scene prepared for higher orders is not drawn by shaders built for lower ones.
    let rt16 = ShRaytrace::new(&gpu, &compiler, opts(16, 1, 1.0)).unwrap();
    let prepared16 = rt16.prepare(&gpu, &high).unwrap();
    let cam = camera(0.0, 0.0, 3.0);
    assert!(rt
        .render_image(&gpu, &prepared16, &cam, (16, 16), BACKGROUND)
        .is_err());
    let one = ParamScene::new(vec![ParamObject::new(glyph8())]);
    let prepared = rt.prepare(&gpu, &one).unwrap();
    assert!(rt
        .render_image(&gpu, &prepared, &cam, (0, 16), BACKGROUND)
        .is_err());
    let view = rt.view(&prepared, &cam, (32, 32)).unwrap();
    let small = Target::new(&gpu, 16, 16).unwrap();
    assert!(rt
        .render_into(&gpu, &prepared, &view, &small, BACKGROUND)
        .is_err());
    assert_clean(&gpu);
}

/// Paper E's large scene, 140 × 140 glyphs of order 12 (19,600), through the grid: every
/// probed hit lies on its glyph and matches the CPU ray tracer.
#[test]
fn large_field_hits_match_the_cpu() {
    let gpu = gpu();
    let side = 140u32;
    let field =
        tessera_data::param::glyph_field::sh_glyph_grid(side, side, 12, NON_LEGACY, 1).unwrap();
    let spacing = 1.0 / side as f32;
    let scene = ParamScene::new(
        field
            .into_iter()
            .map(|g| {
                let to_world = Mat4::from_translation(g.centre * spacing)
                    * Mat4::from_scale(Vec3::splat(0.5 * spacing));
                ParamObject::new(ParamFunction::ShGlyph(g.glyph)).with_transform(to_world)
            })
            .collect(),
    );
    let rt = ShRaytrace::new(&gpu, &shaders::compiler(), opts(12, 1, 1.0)).unwrap();
    let prepared = rt.prepare(&gpu, &scene).unwrap();
    eprintln!("grid {:?}", prepared.grid_dims);
    let objects = scene.reference_objects();
    let grid = GlyphGrid::build(&scene.bounding_spheres(), 1.0).unwrap();
    // (name, camera, 1 / least fraction of pixels covered): the fibre-like glyphs are thin.
    for (name, cam, least) in [
        ("whole", camera(20.0, 55.0, 1.5), 20),
        ("close", camera(20.0, 40.0, 0.12), 10),
    ] {
        let view = rt.view(&prepared, &cam, SIZE).unwrap();
        let (image, ms) = rt
            .render_image(&gpu, &prepared, &cam, SIZE, BACKGROUND)
            .unwrap();
        let bg = pack_rgba8([BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 1.0]);
        let covered = coverage_of(&image, bg).iter().filter(|&&c| c).count();
        let raster: Vec<[f32; 2]> = (0..SIZE.1)
            .step_by(5)
            .flat_map(|y| {
                (0..SIZE.0)
                    .step_by(5)
                    .map(move |x| [x as f32 + 0.5, y as f32 + 0.5])
            })
            .collect();
        let hits = rt.probe(&gpu, &prepared, &view, &raster).unwrap();
        let (mut hit_count, mut unlike) = (0, 0);
        for (p, hit) in raster.iter().zip(&hits) {
            let (eye, dir) = cpu_ray(&view, *p);
            let cpu = trace_glyphs(&objects, &grid, eye, dir);
            let got = (hit.glyph != RayHit::NONE).then_some(hit.glyph);
            match cpu {
                Some((i, t)) if got == Some(i) => {
                    hit_count += 1;
                    assert!(
                        (f64::from(hit.position[3]) - t).abs() < 1e-4,
                        "{name} {p:?}"
                    );
                }
                _ if cpu.map(|c| c.0) == got => {}
                _ => unlike += 1,
            }
        }
        eprintln!(
            "{name}: {covered} pixels covered, GPU {ms:.1} ms; {hit_count} probed hits, {unlike} of {} \
             rays unlike the CPU's",
            raster.len()
        );
        if std::env::var_os("TESSERA_KEEP_IMAGES").is_some() {
            write_png(&out_dir().join(format!("rt-field140-{name}.png")), &image);
        }
        assert!(covered > (SIZE.0 * SIZE.1) as usize / least && hit_count > raster.len() / least);
        assert!(
            unlike * 100 <= raster.len(),
            "{name}: {unlike} rays unlike the CPU's"
        );
    }
    assert_clean(&gpu);
}
