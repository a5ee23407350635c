//! `param-points` (paper E) against the CPU: the SH basis and the parametric functions as the
//! shaders evaluate them, and rendered images against the CPU reference of
//! `tessera_data::param::reference` (the LOD stage is held to the CPU in `param_lod.rs`).

mod common;

use common::camera;
use common::param::*;

use common::{assert_clean, gpu, out_dir, write_png};
use glam::{Mat4, Vec3};
use tessera::param::{
    Footprint, GpuParamScene, ParamObject, ParamPoints, ParamPointsOptions, ParamScene, PointsFrame,
};
use tessera::shaders;
use tessera::target::Target;
use tessera_data::image::coverage_of;
use tessera_data::param::reference::{render_reference, world_position, DEFAULT_MAX_CELL_PX};
use tessera_data::param::sh::{sh_basis, sh_coefficient_count};
use tessera_data::param::{ParamFunction, RadiusNormalization, SeashellParams, ShBasis, ShGlyph};
use tessera_data::shading::pack_rgba8;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

const NON_LEGACY: ShBasis = ShBasis::Descoteaux07 { legacy: false };

// ---------------------------------------------------------------------------------------------
// Functions

/// Directions covering the sphere, both poles included.
fn directions(n: usize) -> Vec<(f32, f32)> {
    let mut out = Vec::new();
    for i in 0..=n {
        for k in 0..2 * n {
            let u = std::f32::consts::PI * i as f32 / n as f32;
            out.push((
                u,
                std::f32::consts::TAU * (k as f32 + 0.37) / (2 * n) as f32,
            ));
        }
    }
    out
}

/// Every basis function as a glyph with one unit coefficient, probed on the GPU, against the
/// CPU basis: order 16 in the non-legacy descoteaux07 basis, order 8 in the three others.
#[test]
fn sh_basis_matches_the_cpu() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let points = ParamPoints::new(&gpu, &compiler, points_opts!()).unwrap();
    let dirs = directions(12);
    for (basis, order) in [
        (NON_LEGACY, 16),
        (ShBasis::Descoteaux07 { legacy: true }, 8),
        (ShBasis::Tournier07 { legacy: true }, 8),
        (ShBasis::Tournier07 { legacy: false }, 8),
    ] {
        let count = sh_coefficient_count(order).unwrap();
        let objects = (0..count)
            .map(|j| {
                let mut c = vec![0.0; count];
                c[j] = 1.0;
                let g = ShGlyph::new(basis, order, c, RadiusNormalization::Raw).unwrap();
                ParamObject::new(ParamFunction::ShGlyph(g))
            })
            .collect();
        let scene = GpuParamScene::upload(&gpu, &ParamScene::new(objects)).unwrap();
        let queries: Vec<(u32, f32, f32)> = (0..count as u32)
            .flat_map(|j| dirs.iter().map(move |&(u, v)| (j, u, v)))
            .collect();
        let results = points.probe(&gpu, &scene, &queries).unwrap();
        assert_eq!(results.len(), queries.len());
        let mut worst = 0.0f64;
        for (i, &(u, v)) in dirs.iter().enumerate() {
            let cpu = sh_basis(basis, order, f64::from(u), f64::from(v)).unwrap();
            for (j, expected) in cpu.iter().enumerate() {
                let got = f64::from(results[j * dirs.len() + i].position[3]);
                let diff = (got - expected).abs();
                assert!(
                    diff <= 1e-5,
                    "{basis:?} order {order}: Y_{j}({u}, {v}) = {got} on the GPU, {expected} on the CPU"
                );
                worst = worst.max(diff);
            }
        }
        eprintln!("{basis:?} order {order}: largest difference {worst:.2e}");
    }
    assert_clean(&gpu);
}

/// Glyph normals, which the shaders take from the SH series' derivatives: orders 4 to 12 in
/// every basis, random coefficients, placed by a non-uniform scale and a rotation. Against an
/// f64 central difference of step 1e-6 of the CPU basis (raw radii, away from the poles) to
/// 1e-5, and against the CPU reference's f32 differences as the other families are held. Where
/// the two differ most (near a zero radius, where the surface turns sharply), the f32
/// differences are the ones off.
#[test]
fn glyph_normals_match_the_cpu() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let points = ParamPoints::new(&gpu, &compiler, points_opts!()).unwrap();
    let mut rng = common::Rng::new(0x2545_f491);
    let mut random = move || rng.range(-0.5, 0.5);
    let place = Mat4::from_scale_rotation_translation(
        Vec3::new(0.6, 0.9, 0.4),
        glam::Quat::from_rotation_y(0.5),
        Vec3::new(0.3, -0.2, 0.1),
    );
    let mut objects = Vec::new();
    for basis in [
        NON_LEGACY,
        ShBasis::Descoteaux07 { legacy: true },
        ShBasis::Tournier07 { legacy: true },
        ShBasis::Tournier07 { legacy: false },
    ] {
        for order in [4, 8, 12] {
            let mut c: Vec<f64> = (0..sh_coefficient_count(order).unwrap())
                .map(|_| random())
                .collect();
            c[0] = 2.0;
            for normalization in [RadiusNormalization::Raw, RadiusNormalization::MinMax] {
                let g = ShGlyph::new(basis, order, c.clone(), normalization).unwrap();
                objects.push(ParamObject::new(ParamFunction::ShGlyph(g)).with_transform(place));
            }
        }
    }
    let scene = ParamScene::new(objects);
    let gpu_scene = GpuParamScene::upload(&gpu, &scene).unwrap();
    let dirs = directions(20);
    let queries: Vec<(u32, f32, f32)> = (0..scene.objects.len() as u32)
        .flat_map(|o| dirs.iter().map(move |&(u, v)| (o, u, v)))
        .collect();
    let results = points.probe(&gpu, &gpu_scene, &queries).unwrap();
    let references = scene.reference_objects();
    let linear = glam::DMat3::from_mat4(place.as_dmat4());
    let (mut worst_exact, mut exact_checked, mut unlike) = (0.0f64, 0, 0);
    for (q, r) in queries.iter().zip(&results) {
        let n = Vec3::from_slice(&r.normal[..3]);
        let object = &scene.objects[q.0 as usize];
        let ParamFunction::ShGlyph(g) = &object.function else {
            unreachable!()
        };
        let (u, v) = (f64::from(q.1), f64::from(q.2));
        if g.normalization() == RadiusNormalization::Raw && u.sin() > 1e-3 {
            let point = |u: f64, v: f64| {
                let y = sh_basis(g.basis(), g.order(), u, v).unwrap();
                let radius: f64 = y.iter().zip(g.coefficients()).map(|(a, b)| a * b).sum();
                linear * (glam::DVec3::new(u.sin() * v.cos(), u.sin() * v.sin(), u.cos()) * radius)
            };
            let h = 1e-6;
            let along_u = (point(u + h, v) - point(u - h, v)) / (2.0 * h);
            let along_v = (point(u, v + h) - point(u, v - h)) / (2.0 * h);
            let exact = along_u.cross(along_v).normalize();
            let cos = n.as_dvec3().dot(exact);
            worst_exact = worst_exact.max(1.0 - cos);
            exact_checked += 1;
            assert!(cos >= 1.0 - 1e-5, "{q:?}: GPU normal {n}, exact {exact}");
        }
        match tessera_data::param::reference::world_normal(&references[q.0 as usize], q.1, q.2) {
            Some(m) if n != Vec3::ZERO && n.dot(m) >= 0.9999 => {}
            None if n == Vec3::ZERO => {}
            other => {
                unlike += 1;
                eprintln!("{q:?}: GPU normal {n}, CPU reference {other:?}");
            }
        }
    }
    eprintln!(
        "{exact_checked} normals within {worst_exact:.2e} (1 - cos) of f64 differences; {unlike} of {} unlike the CPU reference",
        queries.len()
    );
    assert!(
        exact_checked * 3 >= queries.len(),
        "{exact_checked} checked"
    );
    assert!(unlike * 200 <= queries.len(), "{unlike} normals differ");
    assert_clean(&gpu);
}

/// Positions, normals and colours of every family, placed by transforms, against the CPU.
#[test]
fn functions_match_the_cpu() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let points = ParamPoints::new(&gpu, &compiler, points_opts!()).unwrap();
    let scene = trio();
    let gpu_scene = GpuParamScene::upload(&gpu, &scene).unwrap();
    let dirs = directions(24);
    let queries: Vec<(u32, f32, f32)> = (0..3u32)
        .flat_map(|o| dirs.iter().map(move |&(u, v)| (o, u, v)))
        .collect();
    let results = points.probe(&gpu, &gpu_scene, &queries).unwrap();
    let objects = scene.reference_objects();
    let (mut worst_p, mut worst_n, mut unlike) = (0.0f32, 0.0f32, 0);
    for (q, r) in queries.iter().zip(&results) {
        let o = &objects[q.0 as usize];
        let p = world_position(o, q.1, q.2);
        let got = Vec3::from_slice(&r.position[..3]);
        worst_p = worst_p.max((got - p).length());
        assert!((got - p).length() <= 2e-6, "{q:?}: {got} vs {p}");
        let colour = tessera_data::param::reference::base_colour(o, q.1, q.2);
        assert!((Vec3::from_slice(&r.colour[..3]) - colour).length() <= 1e-5);
        let n = Vec3::from_slice(&r.normal[..3]);
        // The heart's bottom tip (u = π) is a cusp: both sides' normals there come from
        // differences of points a rounding error apart (sin π in f32), so they are noise.
        if matches!(o.function, ParamFunction::Heart) && q.1 == std::f32::consts::PI {
            continue;
        }
        match tessera_data::param::reference::world_normal(o, q.1, q.2) {
            Some(m) if n != Vec3::ZERO => {
                worst_n = worst_n.max(1.0 - n.dot(m));
                if n.dot(m).is_nan() || n.dot(m) < 0.9999 {
                    unlike += 1;
                    eprintln!("{q:?}: GPU normal {n}, CPU {m}");
                }
            }
            None if n == Vec3::ZERO => {}
            other => {
                unlike += 1;
                eprintln!("{q:?}: GPU normal {n}, CPU {other:?}");
            }
        }
    }
    eprintln!(
        "positions within {worst_p:.2e}, normals 1 - cos up to {worst_n:.2e}, {unlike} of {} unlike",
        queries.len()
    );
    assert!(unlike * 200 <= queries.len(), "{unlike} normals differ");
    assert_clean(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Images

/// Renders `scene` and holds it to the CPU reference: silhouette IoU >= 0.99 and >= 98 % of the
/// pixels both cover within 4/255, with enough surface in view. Writes PNGs when it fails.
fn assert_image_matches(
    gpu: &Gpu,
    name: &str,
    scene: &ParamScene,
    cam: &OrbitCamera,
    options: ParamPointsOptions,
) -> f64 {
    assert_image_matches_within(gpu, name, scene, cam, options, ImageBar::default())
}

/// What [`assert_image_matches_within`] holds an image to.
struct ImageBar {
    size: (u32, u32),
    /// The least share of the co-covered pixels within 4/255.
    min_within: f64,
    /// The largest share of them more than 16/255 off (pinholes show the far side).
    max_far_off: f64,
}

impl Default for ImageBar {
    fn default() -> Self {
        ImageBar {
            size: SIZE,
            min_within: 0.98,
            max_far_off: 1.0,
        }
    }
}

/// [`assert_image_matches`] held to `bar`.
fn assert_image_matches_within(
    gpu: &Gpu,
    name: &str,
    scene: &ParamScene,
    cam: &OrbitCamera,
    options: ParamPointsOptions,
    bar: ImageBar,
) -> f64 {
    let size = bar.size;
    let compiler = shaders::compiler();
    let points = ParamPoints::new(gpu, &compiler, options).unwrap();
    let gpu_scene = GpuParamScene::upload(gpu, scene).unwrap();
    let view = points.view(&gpu_scene, cam, size).unwrap();
    let frame = PointsFrame::new(gpu, &view).unwrap();
    let pixels = Target::new(gpu, size.0, size.1).unwrap();
    pixels.poison(gpu, POISON).unwrap();
    let info = points
        .render_frame(gpu, &gpu_scene, &view, &frame, &pixels, BACKGROUND)
        .unwrap();
    let image = pixels.read(gpu).unwrap();
    assert!(
        !image.pixels.contains(&POISON),
        "{name}: pixels never written"
    );
    let objects = scene.reference_objects();
    let reference =
        render_reference(&objects, &view.reference(), BACKGROUND, DEFAULT_MAX_CELL_PX).unwrap();
    let (iou, within, covered) = compare(&image, &reference);
    let far_off = 1.0 - far_within(&image, &reference);
    eprintln!(
        "{name}: IoU {iou:.4}, {:.2}% of co-covered pixels within 4/255, {:.3}% more than \
         16/255 off, {covered} covered, {} patches, GPU {:.1} ms",
        within * 100.0,
        far_off * 100.0,
        info.stats.rendered,
        info.gpu_ms
    );
    let (w, h) = size;
    if std::env::var_os("TESSERA_KEEP_IMAGES").is_some() {
        write_png(&out_dir().join(format!("param-{name}-actual.png")), &image);
        write_png(
            &out_dir().join(format!("param-{name}-expected.png")),
            &reference,
        );
    }
    if iou < 0.99
        || within < bar.min_within
        || far_off > bar.max_far_off
        || covered < (w * h / 10) as usize
        || info.stats.skipped_cells > 0
    {
        let dir = out_dir();
        write_png(&dir.join(format!("param-{name}-actual.png")), &image);
        write_png(&dir.join(format!("param-{name}-expected.png")), &reference);
        write_png(
            &dir.join(format!("param-{name}-diff.png")),
            &image.diff_image(&reference),
        );
        panic!(
            "{name}: IoU {iou}, within {within}, {far_off} more than 16/255 off, covered {covered}, \
             skipped cells {}; images in {}",
            info.stats.skipped_cells,
            dir.display()
        );
    }
    info.gpu_ms
}

#[test]
fn sphere_image_matches_the_reference() {
    let gpu = gpu();
    let sphere = one(ParamFunction::Sphere);
    assert_image_matches(
        &gpu,
        "sphere",
        &sphere,
        &camera(30.0, 20.0, 3.5),
        points_opts!(),
    );
    assert_clean(&gpu);
}

#[test]
fn heart_image_matches_the_reference() {
    let gpu = gpu();
    let heart = one(ParamFunction::Heart);
    assert_image_matches(
        &gpu,
        "heart",
        &heart,
        &camera(-30.0, 15.0, 2.6),
        points_opts!(),
    );
    assert_clean(&gpu);
}

#[test]
fn glyph_image_matches_the_reference() {
    let gpu = gpu();
    let glyph = one(glyph8());
    assert_image_matches(
        &gpu,
        "glyph",
        &glyph,
        &camera(60.0, -25.0, 2.4),
        points_opts!(),
    );
    // Mirrored, its cells wind the other way on screen: those facing the eye still drawn.
    let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let mirrored = ParamScene::new(vec![ParamObject::new(glyph8())
        .with_colour([0.9, 0.6, 0.3])
        .with_transform(mirror)]);
    assert_image_matches(
        &gpu,
        "glyph-mirrored",
        &mirrored,
        &camera(60.0, -25.0, 2.4),
        points_opts!(),
    );
    assert_clean(&gpu);
}

/// The glyph seen from within, where every cell in view faces away from the eye. Up close the
/// cells are many pixels wide and the GPU's interpolation and the CPU's part more often (92.7 %
/// of the pixels within 4/255), so the bar is lower; cells facing away left undrawn would leave
/// the image empty (IoU 0.013).
#[test]
fn glyph_seen_from_inside_matches_the_reference() {
    let gpu = gpu();
    assert_image_matches_within(
        &gpu,
        "glyph-inside",
        &one(glyph8()),
        &camera(60.0, -25.0, 0.15),
        points_opts!(),
        ImageBar {
            min_within: 0.9,
            ..ImageBar::default()
        },
    );
    assert_clean(&gpu);
}

/// A close-up of an order-12 glyph: the patches at the two ends of its azimuth meet along a
/// meridian, each sampling it at its own count; unless they overlap there, the seam leaves a
/// dotted line of pinholes through to the far side (on lavapipe 0.089 % of the co-covered
/// pixels more than 16/255 off; 0.014 % with the overlap).
#[test]
fn glyph_close_up_has_no_pinholes_along_its_seam() {
    let gpu = gpu();
    let data =
        tessera_data::scene::Dataset::load("param:sh-glyph:order12", &Default::default()).unwrap();
    let tessera_data::scene::Dataset::Param(glyph) = data else {
        unreachable!()
    };
    assert_image_matches_within(
        &gpu,
        "glyph-seam",
        &glyph.scene,
        &camera(30.0, 20.0, 1.8),
        points_opts!(),
        ImageBar {
            size: (400, 400),
            max_far_off: 0.0004,
            ..ImageBar::default()
        },
    );
    assert_clean(&gpu);
}

/// Three objects (payload with object bits), close enough that some patches are off screen,
/// supersampled 2x2 on both sides.
#[test]
fn scene_and_supersampling_match_the_reference() {
    let gpu = gpu();
    assert_image_matches(
        &gpu,
        "trio",
        &trio(),
        &camera(25.0, 10.0, 3.2),
        points_opts!(),
    );
    let ss = points_opts!(supersample: 2);
    assert_image_matches(
        &gpu,
        "sphere-ss2",
        &one(ParamFunction::Sphere),
        &camera(-50.0, 40.0, 3.5),
        ss,
    );
    assert_clean(&gpu);
}

/// The paper's own footprint (each sample writes its pixel) at twice the density: no holes
/// inside the reference's silhouette, nothing beyond a pixel outside it.
#[test]
fn pixel_footprint_covers_the_silhouette() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let opts = points_opts!(footprint: Footprint::Pixel, density: 2.0);
    let points = ParamPoints::new(&gpu, &compiler, opts).unwrap();
    let scene = one(glyph8());
    let gpu_scene = GpuParamScene::upload(&gpu, &scene).unwrap();
    let cam = camera(60.0, -25.0, 2.4);
    let (image, ms) = points
        .render_image(&gpu, &gpu_scene, &cam, SIZE, BACKGROUND)
        .unwrap();
    let view = points.view(&gpu_scene, &cam, SIZE).unwrap();
    let reference = render_reference(
        &scene.reference_objects(),
        &view.reference(),
        BACKGROUND,
        DEFAULT_MAX_CELL_PX,
    )
    .unwrap();
    let bg = pack_rgba8([BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 1.0]);
    let (a, b) = (coverage_of(&image, bg), coverage_of(&reference, bg));
    let (w, h) = (SIZE.0 as i32, SIZE.1 as i32);
    let around = |mask: &[bool], x: i32, y: i32, want: bool| {
        (-1..=1).any(|dy| {
            (-1..=1).any(|dx| {
                let (px, py) = (x + dx, y + dy);
                px >= 0 && py >= 0 && px < w && py < h && mask[(py * w + px) as usize] == want
            })
        })
    };
    let (mut holes, mut outside) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            holes += usize::from(b[i] && !a[i] && !around(&b, x, y, false));
            outside += usize::from(a[i] && !around(&b, x, y, true));
        }
    }
    let (iou, within, covered) = compare(&image, &reference);
    eprintln!(
        "pixel footprint: {holes} holes, {outside} pixels outside, IoU {iou:.4}, {:.1}% within \
         4/255, {covered} covered, GPU {ms:.1} ms",
        within * 100.0
    );
    assert!(covered > (w * h / 10) as usize);
    assert_eq!((holes, outside), (0, 0));
    assert_clean(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn bad_input_is_refused() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    for bad in [
        points_opts!(supersample: 0),
        points_opts!(density: 0.0),
        points_opts!(max_steps: 0),
        points_opts!(thresholds: [f32::NAN, 4.0]),
        points_opts!(patch_capacity: 0),
    ] {
        assert!(ParamPoints::new(&gpu, &compiler, bad).is_err(), "{bad:?}");
    }
    assert!(GpuParamScene::upload(&gpu, &ParamScene::default()).is_err());
    // A seashell without turns is no surface.
    let shell = ParamScene::new(vec![ParamObject::new(ParamFunction::Seashell(
        SeashellParams {
            turns: 0.0,
            ..SeashellParams::default()
        },
    ))]);
    assert!(GpuParamScene::upload(&gpu, &shell).is_err());
    let flat = ParamScene::new(vec![
        ParamObject::new(ParamFunction::Sphere).with_transform(Mat4::from_scale(Vec3::ZERO))
    ]);
    assert!(GpuParamScene::upload(&gpu, &flat).is_err());

    // Lists of 8 patches cannot hold a close sphere's LOD: the frame is refused, not drawn.
    let small = points_opts!(patch_capacity: 8);
    let points = ParamPoints::new(&gpu, &compiler, small).unwrap();
    let scene = GpuParamScene::upload(&gpu, &one(ParamFunction::Sphere)).unwrap();
    let cam = camera(0.0, 0.0, 2.0);
    for size in [SIZE, (0, 10)] {
        assert!(points
            .render_image(&gpu, &scene, &cam, size, BACKGROUND)
            .is_err());
    }
    assert!(points.probe(&gpu, &scene, &[(1, 0.0, 0.0)]).is_err());
    // More objects than a list holds: refused too.
    let two = ParamPoints::new(&gpu, &compiler, points_opts!(patch_capacity: 2)).unwrap();
    let three = GpuParamScene::upload(&gpu, &trio()).unwrap();
    let far = camera(0.0, 0.0, 20.0);
    assert!(two
        .render_image(&gpu, &three, &far, SIZE, BACKGROUND)
        .is_err());
    assert_clean(&gpu);
}
