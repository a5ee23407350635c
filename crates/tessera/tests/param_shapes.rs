//! The seashell and the knit yarn tubes of paper E (§5) on the GPU against the CPU: positions
//! and normals of both functions as the shaders evaluate them (probe pass), their object bounds,
//! the curtain helper's layout, and images by `param-points` and `param-tess` against the CPU
//! reference of `tessera_data::param::reference`.

mod common;

use common::camera;
use common::param::*;

use common::{assert_clean, gpu, out_dir, write_png};
use glam::{Mat4, Quat, Vec3};
use tessera::param::scenes::{curtain_knit, seashell, yarn_curtain, yarn_curtain_of};
use tessera::param::tess::{ParamTess, ParamTessOptions, TessLevels};
use tessera::param::{
    GpuParamScene, ParamObject, ParamPoints, ParamPointsOptions, ParamScene, PointsFrame, View,
};
use tessera::shaders;
use tessera::target::Target;
use tessera_data::param::reference::{
    render_reference, world_normal, world_position, DEFAULT_MAX_CELL_PX,
};
use tessera_data::param::{KnitCurve, KnitParams, ParamFunction, SeashellParams, YarnTube};
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// GPU positions against the CPU's, as a fraction of the object's world bound radius. Lavapipe
/// stays within 3e-7 for both families (a few f32 roundings). The seashell's CPU is f32 too, so
/// the two differ only where their sin, cos, exp and division do; Vulkan lets a division be off
/// by 2.5 ulp, and the nodule phase `t` reaches 560 for the fine-bump shell (70 nodules over 8
/// turns), whose nodules' slope turns that 1.5e-4 in `t` into about 1e-5 of the size; f32 sines
/// of spiral angles up to 50 can be off by an ulp of the angle (4e-6). 5e-5 covers both and is
/// still 0.025 px on a shell 500 px across. The yarn's CPU is f64, its GPU arguments stay small
/// (fibre angles up to 130 give 1.5e-5 radians on a 0.5 fibre offset, 3e-7 of the 27 bound):
/// 1e-5. A wrong formula, constant or axis errs by 1e-3 or more.
const SHELL_TOLERANCE: f32 = 5e-5;
const YARN_TOLERANCE: f32 = 1e-5;

fn shells() -> [SeashellParams; 3] {
    [
        SeashellParams::default(),
        SeashellParams::ridged(),
        SeashellParams::fine_bumps(),
    ]
}

/// The curtain's knit with a twist that is no whole number, so that fibres do not repeat with
/// the loop.
fn odd_twist() -> KnitParams {
    KnitParams {
        twist: 4.3,
        ..curtain_knit()
    }
}

/// A yarn and its six fibres over Crane's default four loops (`u` up to 8π), and the fibres of
/// a knit with a twist that is not a whole number.
fn tubes() -> Vec<YarnTube> {
    let knit = KnitParams::default();
    let mut out = vec![YarnTube::new(knit, KnitCurve::Yarn, 0.8).unwrap()];
    out.extend(YarnTube::fibers(knit, 6, 0.3).unwrap());
    let odd = KnitParams { twist: 4.3, ..knit };
    out.extend(YarnTube::fibers(odd, 3, 0.2).unwrap());
    out
}

/// `nu × nv` parameters over `f`'s domain, both ends of both ranges included.
fn grid(f: &ParamFunction, nu: u32, nv: u32) -> Vec<(f32, f32)> {
    let d = f.domain();
    let at = |r: [f32; 2], i: u32, n: u32| match i {
        0 => r[0],
        _ if i == n => r[1],
        _ => r[0] + (r[1] - r[0]) * i as f32 / n as f32,
    };
    (0..=nu)
        .flat_map(|i| (0..=nv).map(move |j| (at(d.u, i, nu), at(d.v, j, nv))))
        .collect()
}

/// Objects placed by turned, scaled and moved transforms.
fn placed(functions: Vec<ParamFunction>) -> ParamScene {
    ParamScene::new(
        functions
            .into_iter()
            .enumerate()
            .map(|(i, f)| {
                let x = i as f32;
                ParamObject::new(f).with_transform(Mat4::from_scale_rotation_translation(
                    Vec3::new(0.3, 0.25, 0.35) * (1.0 + 0.1 * x),
                    Quat::from_euler(glam::EulerRot::XYZ, 0.3 * x, 0.7, -0.2 * x),
                    Vec3::new(x - 1.0, 0.5, -0.3 * x),
                ))
            })
            .collect(),
    )
}

/// Every object of `scene` probed on an `nu × nv` grid: (object, u, v) and the GPU's results.
fn probe_all(
    gpu: &Gpu,
    scene: &ParamScene,
    nu: u32,
    nv: u32,
) -> Vec<((u32, f32, f32), tessera::param::ProbeResult)> {
    let points = ParamPoints::new(gpu, &shaders::compiler(), Default::default()).unwrap();
    let gpu_scene = GpuParamScene::upload(gpu, scene).unwrap();
    let queries: Vec<(u32, f32, f32)> = (scene.objects.iter().enumerate())
        .flat_map(|(o, obj)| {
            grid(&obj.function, nu, nv)
                .into_iter()
                .map(move |(u, v)| (o as u32, u, v))
        })
        .collect();
    let results = points.probe(gpu, &gpu_scene, &queries).unwrap();
    queries.into_iter().zip(results).collect()
}

/// GPU positions within `tolerance` times each object's world bound radius of the CPU's, and
/// normals alike (1 - cos ≤ 1e-4) at ≥ 99.5 % of the points.
fn assert_positions_match(gpu: &Gpu, name: &str, scene: &ParamScene, tolerance: f32) {
    let objects = scene.reference_objects();
    let sizes: Vec<f32> = scene.bounding_spheres().iter().map(|b| b.1).collect();
    let probed = probe_all(gpu, scene, 600, 48);
    let (mut worst, mut unlike) = (0.0f32, 0);
    for ((o, u, v), r) in &probed {
        let object = &objects[*o as usize];
        let cpu = world_position(object, *u, *v);
        let got = Vec3::from_slice(&r.position[..3]);
        let error = (got - cpu).length() / sizes[*o as usize];
        assert!(
            error <= tolerance,
            "{name} object {o} ({u}, {v}): {got} vs {cpu}"
        );
        worst = worst.max(error);
        let n = Vec3::from_slice(&r.normal[..3]);
        match world_normal(object, *u, *v) {
            Some(m) if n.dot(m) >= 0.9999 => {}
            _ => unlike += 1,
        }
    }
    eprintln!(
        "{name}: positions within {worst:.2e} of the bound radius, {unlike} of {} normals unlike",
        probed.len()
    );
    assert!(
        unlike * 200 <= probed.len(),
        "{name}: {unlike} normals differ"
    );
}

/// Analytic tangents of the fibres (CPU) against an f64 difference quotient of the fibre curve.
#[test]
fn fibre_velocity_is_the_derivative() {
    for knit in [KnitParams::default(), odd_twist()] {
        for i in 0..200 {
            let (t, phase) = (i as f64 * 0.131 - 3.0, i as f64 * 0.7);
            let h = 1e-5;
            let diff =
                (knit.fiber_curve(t + h, phase) - knit.fiber_curve(t - h, phase)) / (2.0 * h);
            let exact = knit.fiber_velocity(t, phase);
            assert!(
                (diff - exact).length() < 1e-7 * exact.length(),
                "{t}: {diff} vs {exact}"
            );
        }
    }
}

/// The three seashell variants, placed by transforms, evaluated by the shaders.
#[test]
fn seashell_matches_the_cpu() {
    let gpu = gpu();
    let scene = placed(shells().map(ParamFunction::Seashell).to_vec());
    assert_positions_match(&gpu, "seashells", &scene, SHELL_TOLERANCE);
    assert_clean(&gpu);
}

/// Yarn and fibre tubes over four loops, and a curtain's one-loop tubes in place.
#[test]
fn yarn_matches_the_cpu() {
    let gpu = gpu();
    let scene = placed(tubes().into_iter().map(ParamFunction::Yarn).collect());
    assert_positions_match(&gpu, "tubes", &scene, YARN_TOLERANCE);
    let curtain = yarn_curtain_of(odd_twist(), 2, 2, true).unwrap();
    assert_positions_match(&gpu, "curtain", &curtain, YARN_TOLERANCE);
    assert_clean(&gpu);
}

/// Every object's surface, probed on the GPU on a dense grid and evaluated on the CPU, lies in
/// its object-space bound, which the points come close to (so the grid reaches the surface's
/// far side); a curtain's points lie in their world bounding spheres.
#[test]
fn bounds_hold() {
    let gpu = gpu();
    let wide = KnitParams {
        roundness: -2.0,
        height: 3.0,
        depth: 2.5,
        ..KnitParams::default()
    };
    // A spiral that shrinks (α > 90°, largest radius at θ = 0) with sunken nodules.
    let shrinking = SeashellParams {
        alpha_deg: 93.0,
        turns: 3.0,
        nodule_height_along: -8.0,
        ..SeashellParams::default()
    };
    let mut functions: Vec<ParamFunction> = shells().map(ParamFunction::Seashell).to_vec();
    functions.push(ParamFunction::Seashell(shrinking));
    functions.extend(tubes().into_iter().map(ParamFunction::Yarn));
    functions.push(ParamFunction::Yarn(
        YarnTube::new(wide, KnitCurve::Fiber { phase: 1.0 }, 0.4).unwrap(),
    ));
    functions.push(ParamFunction::Yarn(
        YarnTube::new(curtain_knit(), KnitCurve::Yarn, 0.8).unwrap(),
    ));
    let scene = ParamScene::new(functions.into_iter().map(ParamObject::new).collect());
    let mut reach = vec![0.0f32; scene.objects.len()];
    for ((o, u, v), r) in probe_all(&gpu, &scene, 2000, 64) {
        let object = &scene.objects[o as usize];
        let bound = object.object_radius();
        let gpu_p = Vec3::from_slice(&r.position[..3]).length();
        let cpu_p = object.function.position(u, v).length();
        assert!(
            gpu_p <= bound && cpu_p <= bound,
            "object {o} ({u}, {v}): {gpu_p} {cpu_p} > {bound}"
        );
        reach[o as usize] = reach[o as usize].max(gpu_p / bound);
    }
    eprintln!("largest |f| / bound per object: {reach:.3?}");
    assert!(reach.iter().all(|&r| r > 0.8), "{reach:?}");

    let curtain = yarn_curtain(2, 3, true).unwrap();
    let spheres = curtain.bounding_spheres();
    for ((o, _, _), r) in probe_all(&gpu, &curtain, 200, 16) {
        let (centre, radius) = spheres[o as usize];
        assert!(Vec3::from_slice(&r.position[..3]).distance(centre) <= radius);
    }
    assert_clean(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Images

/// How finely both techniques sample: the paper's settings (the options' defaults: LOD
/// threshold 84 px, one point per pixel, one tessellation segment per pixel), or two samples
/// per pixel (points at density 2; segments of half a pixel, with a 32 px threshold so that the
/// level cap of 64 still allows them).
#[derive(Clone, Copy, PartialEq)]
enum Sampling {
    Paper,
    Twice,
}

fn options(sampling: Sampling) -> (ParamPointsOptions, ParamTessOptions) {
    match sampling {
        Sampling::Paper => Default::default(),
        Sampling::Twice => (
            ParamPointsOptions {
                density: 2.0,
                thresholds: [32.0; 2],
                ..Default::default()
            },
            ParamTessOptions {
                thresholds: [32.0; 2],
                levels: TessLevels::Adaptive {
                    pixels_per_segment: 0.5,
                },
                ..Default::default()
            },
        ),
    }
}

/// `scene` by param-points and by param-tess (adaptive levels), each held to the CPU reference
/// as the other param tests hold theirs: silhouette IoU ≥ 0.99, ≥ 98 % of co-covered pixels
/// within 4/255, at least 5 % of the image covered, every pixel written. PNGs when it fails
/// (or with TESSERA_KEEP_IMAGES).
fn assert_images_match(
    gpu: &Gpu,
    name: &str,
    scene: &ParamScene,
    cam: &OrbitCamera,
    size: (u32, u32),
    sampling: Sampling,
) {
    let compiler = shaders::compiler();
    let gpu_scene = GpuParamScene::upload(gpu, scene).unwrap();
    let (points_options, tess_options) = options(sampling);
    let points = ParamPoints::new(gpu, &compiler, points_options).unwrap();
    let tess = ParamTess::new(gpu, &compiler, tess_options).unwrap();
    let view: View = points.view(&gpu_scene, cam, size).unwrap();
    assert_eq!(view, tess.view(&gpu_scene, cam, size).unwrap());
    let clock = std::time::Instant::now();
    let objects = scene.reference_objects();
    let reference =
        render_reference(&objects, &view.reference(), BACKGROUND, DEFAULT_MAX_CELL_PX).unwrap();
    let reference_s = clock.elapsed().as_secs_f64();

    let pixels = Target::new(gpu, size.0, size.1).unwrap();
    let frame = PointsFrame::new(gpu, &view).unwrap();
    pixels.poison(gpu, POISON).unwrap();
    let info = (points.render_frame(gpu, &gpu_scene, &view, &frame, &pixels, BACKGROUND)).unwrap();
    let by_points = (pixels.read(gpu).unwrap(), info);
    drop(frame);
    let frame = tess.frame(gpu, &view).unwrap();
    pixels.poison(gpu, POISON).unwrap();
    let info = (tess.render_frame(gpu, &gpu_scene, &view, &frame, &pixels, BACKGROUND)).unwrap();
    let by_tess = (pixels.read(gpu).unwrap(), info);

    let mut failures = Vec::new();
    for (technique, (image, info)) in [("points", by_points), ("tess", by_tess)] {
        let (iou, within, covered) = compare(&image, &reference);
        let cover = covered as f64 / f64::from(size.0 * size.1);
        eprintln!(
            "{name} {technique}: IoU {iou:.4}, {:.2}% of co-covered pixels within 4/255, \
             {:.0}% covered, {} patches, GPU {:.1} ms (reference {reference_s:.1} s)",
            within * 100.0,
            cover * 100.0,
            info.stats.rendered,
            info.gpu_ms
        );
        let unwritten = image.pixels.contains(&POISON);
        let failed = unwritten || iou < 0.99 || within < 0.98 || cover < 0.05;
        if failed || std::env::var_os("TESSERA_KEEP_IMAGES").is_some() {
            let dir = out_dir();
            let diff = image.diff_image(&reference);
            write_png(&dir.join(format!("shapes-{name}-{technique}.png")), &image);
            write_png(&dir.join(format!("shapes-{name}-expected.png")), &reference);
            write_png(
                &dir.join(format!("shapes-{name}-{technique}-diff.png")),
                &diff,
            );
        }
        if failed {
            failures.push(format!(
                "{technique}: IoU {iou}, within {within}, cover {cover}, unwritten {unwritten}"
            ));
        }
    }
    let dir = out_dir();
    assert!(
        failures.is_empty(),
        "{name}: {failures:?}; images in {}",
        dir.display()
    );
}

/// Variant 1 of the authors' shell. Its sharp nodules change shading within a pixel, and the LOD
/// stage measures patch extents between samples, so nodule flanks get fewer samples than
/// pixels: at the paper's one sample per pixel the images match from 512² (96-97 % of pixels
/// within 4/255 at 256², 98.4-98.6 % at 400²); at two samples per pixel from 256².
#[test]
fn seashell_images_match_the_reference() {
    let gpu = gpu();
    let shell = seashell(SeashellParams::default()).unwrap();
    let cam = camera(35.0, 25.0, 1.7);
    assert_images_match(&gpu, "seashell", &shell, &cam, (512, 512), Sampling::Paper);
    let side = camera(-60.0, 10.0, 1.7);
    let twice = Sampling::Twice;
    assert_images_match(&gpu, "seashell-twice", &shell, &side, (256, 256), twice);
    assert_clean(&gpu);
}

/// Two rows of two loops, as yarn tubes and as six fibre tubes per yarn, at the paper's
/// sampling. The yarn tubes (about 14 px across here) match at 160²; the fibre tubes need 320²
/// (about 10 px across): shading turns by about a quarter radian per pixel across a tube 5 px
/// wide, so the tenth of a pixel by which a surface sample can land off the pixel centre
/// already moves colours past 4/255 (95 % of pixels within at 160², 99 % at 256²).
#[test]
fn curtain_images_match_the_reference() {
    let gpu = gpu();
    let cam = camera(20.0, 15.0, 2.0);
    let yarn = yarn_curtain(2, 2, false).unwrap();
    assert_images_match(
        &gpu,
        "curtain-yarn",
        &yarn,
        &cam,
        (160, 160),
        Sampling::Paper,
    );
    let fibres = yarn_curtain(2, 2, true).unwrap();
    assert_images_match(
        &gpu,
        "curtain-fibres",
        &fibres,
        &cam,
        (320, 320),
        Sampling::Paper,
    );
    assert_clean(&gpu);
}

/// What the shaders cannot evaluate is refused at upload: a seashell the CPU deems invalid, a
/// yarn whose parameters overflow f32.
#[test]
fn bad_shapes_are_refused() {
    let gpu = gpu();
    let flat = SeashellParams {
        turns: 0.0,
        ..SeashellParams::default()
    };
    let huge = KnitParams {
        height: 1e40,
        ..KnitParams::default()
    };
    let tube = YarnTube::new(huge, KnitCurve::Yarn, 0.5).unwrap();
    for f in [ParamFunction::Seashell(flat), ParamFunction::Yarn(tube)] {
        let scene = ParamScene::new(vec![ParamObject::new(f)]);
        assert!(GpuParamScene::upload(&gpu, &scene).is_err());
    }
    assert!(seashell(flat).is_err());
    assert_clean(&gpu);
}
