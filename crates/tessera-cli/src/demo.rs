//! `tessera demo`: a gallery from built-in procedural data, no files needed.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use tessera::iso::renderer::{IsoRenderer, IsoTechnique};
use tessera::path::PathChoice;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{IsoValue, OrbitCamera, ScalarType};
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct DemoArgs {
    /// Folder for the PNGs.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Samples per axis of the procedural volumes.
    #[arg(long, default_value_t = 128)]
    volume_size: u32,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 384)]
    image_size: u32,
}

struct Scene {
    technique: IsoTechnique,
    kind: ProceduralKind,
    scalar: ScalarType,
    iso_fraction: f32,
    camera: OrbitCamera,
}

fn scenes() -> Vec<Scene> {
    let cam = |az: f32, el: f32| OrbitCamera {
        azimuth_deg: az,
        elevation_deg: el,
        distance: 1.9,
        eye_shift: 0.0,
        fov_y_deg: 40.0,
    };
    vec![
        Scene {
            technique: IsoTechnique::Raymarch,
            kind: ProceduralKind::Sphere,
            scalar: ScalarType::U8,
            iso_fraction: 0.7,
            camera: cam(30.0, 20.0),
        },
        Scene {
            technique: IsoTechnique::Raymarch,
            kind: ProceduralKind::MarschnerLobb,
            scalar: ScalarType::U16,
            iso_fraction: 0.5,
            camera: cam(20.0, 35.0),
        },
        Scene {
            technique: IsoTechnique::Raymarch,
            kind: ProceduralKind::HeadPhantom,
            scalar: ScalarType::U8,
            iso_fraction: 0.2,
            camera: cam(40.0, 15.0),
        },
        Scene {
            technique: IsoTechnique::Raymarch,
            kind: ProceduralKind::HeadPhantom,
            scalar: ScalarType::U8,
            iso_fraction: 0.8,
            camera: cam(40.0, 15.0),
        },
        Scene {
            technique: IsoTechnique::Raymarch,
            kind: ProceduralKind::Turbulence,
            scalar: ScalarType::F32,
            iso_fraction: 0.55,
            camera: cam(25.0, 30.0),
        },
        Scene {
            technique: IsoTechnique::Direct,
            kind: ProceduralKind::MarschnerLobb,
            scalar: ScalarType::U16,
            iso_fraction: 0.5,
            camera: cam(20.0, 35.0),
        },
        Scene {
            technique: IsoTechnique::Direct,
            kind: ProceduralKind::Turbulence,
            scalar: ScalarType::F32,
            iso_fraction: 0.55,
            camera: cam(25.0, 30.0),
        },
    ]
}

pub fn run(options: &GpuOptions, args: &DemoArgs) -> Result<()> {
    let gpu = crate::open_gpu(options)?;
    let compiler = tessera::shaders::compiler();
    println!(
        "device: {} ({})",
        gpu.caps().device_name,
        gpu.caps().driver_info
    );
    let size = args.image_size;
    for scene in scenes() {
        let volume = generate(scene.kind, args.volume_size, scene.scalar)?;
        let iso = volume.iso_to_texel(IsoValue::Normalized(scene.iso_fraction));
        let started = Instant::now();
        let renderer = match IsoRenderer::new(
            &gpu,
            &compiler,
            scene.technique,
            scene.scalar,
            PathChoice::Auto,
        ) {
            Ok(r) => r,
            Err(e) => {
                println!(
                    "skipped {} on {}: {e}",
                    scene.technique.name(),
                    volume.name()
                );
                continue;
            }
        };
        let prepared = renderer.prepare(&gpu, &volume)?;
        let frame = renderer.render(&gpu, &prepared, iso, &scene.camera, (size, size), true)?;
        let wall_ms = started.elapsed().as_secs_f64() * 1e3;
        let label = format!("{} ({})", scene.technique.name(), renderer.path().name());
        let path = args.out.join(format!(
            "{}-{}-iso{:.2}.png",
            scene.technique.name(),
            volume.name(),
            scene.iso_fraction
        ));
        crate::output::write_png(&path, &frame.image)?;
        println!(
            "{:<60} {label:<20} {:>9.2} ms GPU, {:>8.1} ms with upload and octree build",
            path.display(),
            frame.gpu_ms,
            wall_ms
        );
    }
    interval_scene(&gpu, &compiler, args)?;
    parametric_scenes(&gpu, &compiler, args)?;
    crate::check_validation(&gpu)
}

/// A tetrahedral sphere with per-tet absorption colours seen against a light, and its radius
/// field through a transfer function as emission (interval shading, every path the device has).
fn interval_scene(
    gpu: &tessera_gpu::Gpu,
    compiler: &tessera_gpu::ShaderCompiler,
    args: &DemoArgs,
) -> Result<()> {
    use tessera::path::Path;
    use tessera::tet::interval::{path_support, GpuTetMesh, Integrand, Interval, IntervalOptions};
    use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction, TABLE_KNOTS};
    let mesh = tessera_data::tet::procedural::sphere_mesh((args.volume_size / 8).max(2));
    let emission = Integrand::Scalar {
        mode: ScalarMode::Emission,
        table: IntegrandTable::new(
            &TransferFunction::preset("hot")?,
            ScalarMode::Emission,
            3.0,
            TABLE_KNOTS,
        ),
    };
    let camera = OrbitCamera {
        distance: 2.2,
        ..OrbitCamera::default()
    };
    let support = path_support(gpu.caps());
    let paths = [
        (Path::Graphics, support.graphics),
        (Path::Compute, support.compute),
    ];
    for (path, supported) in paths {
        if !supported {
            println!(
                "skipped interval ({} path): the device lacks its features",
                path.name()
            );
            continue;
        }
        for (name, integrand, background) in [
            ("absorption", Integrand::TetAbsorption, [1.0, 0.97, 0.9]),
            ("emission", emission.clone(), [0.02, 0.02, 0.03]),
        ] {
            let started = Instant::now();
            let options = IntervalOptions {
                integrand,
                ..IntervalOptions::new(path)
            };
            let interval = Interval::new(gpu, compiler, &options)?;
            let gpu_mesh = GpuTetMesh::upload(gpu, &mesh)?;
            let size = args.image_size;
            let (image, gpu_ms) =
                interval.render_image(gpu, &gpu_mesh, &camera, (size, size), background)?;
            let wall_ms = started.elapsed().as_secs_f64() * 1e3;
            let file = args.out.join(format!(
                "interval-sphere-{}tets-{name}-{}.png",
                mesh.tets.len(),
                path.name()
            ));
            crate::output::write_png(&file, &image)?;
            println!(
                "{:<60} {:<20} {:>9.2} ms GPU, {:>8.1} ms with upload",
                file.display(),
                format!("interval ({})", path.name()),
                gpu_ms,
                wall_ms
            );
        }
        asteroid_scene(gpu, compiler, args, path)?;
    }
    Ok(())
}

/// Paper A's asteroid field: one bounding tet per asteroid, sphere-traced along its interval.
fn asteroid_scene(
    gpu: &tessera_gpu::Gpu,
    compiler: &tessera_gpu::ShaderCompiler,
    args: &DemoArgs,
    path: tessera::path::Path,
) -> Result<()> {
    use tessera::tet::interval::{GpuTetMesh, Integrand, Interval, IntervalOptions};
    if path == tessera::path::Path::Compute && !gpu.caps().buffer_int64_atomics {
        println!("skipped asteroids (compute path): the device lacks 64-bit atomics");
        return Ok(());
    }
    let started = Instant::now();
    let mesh = tessera_data::tet::asteroids::asteroid_field(200, 1);
    let options = IntervalOptions {
        integrand: Integrand::Asteroids,
        ..IntervalOptions::new(path)
    };
    let interval = Interval::new(gpu, compiler, &options)?;
    let gpu_mesh = GpuTetMesh::upload_asteroids(gpu, &mesh)?;
    let camera = OrbitCamera {
        distance: 1.5,
        ..OrbitCamera::default()
    };
    let size = args.image_size;
    let (image, gpu_ms) =
        interval.render_image(gpu, &gpu_mesh, &camera, (size, size), [0.02; 3])?;
    let file = args.out.join(format!("asteroids-200-{}.png", path.name()));
    crate::output::write_png(&file, &image)?;
    println!(
        "{:<60} {:<20} {:>9.2} ms GPU, {:>8.1} ms with upload",
        file.display(),
        format!("asteroids ({})", path.name()),
        gpu_ms,
        started.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// Paper E's parametric objects: a heart by points, SH glyphs by tessellation and by ray
/// tracing, a seashell and a knitted curtain.
fn parametric_scenes(
    gpu: &tessera_gpu::Gpu,
    compiler: &tessera_gpu::ShaderCompiler,
    args: &DemoArgs,
) -> Result<()> {
    use crate::param_renderer::ParamRenderer;
    let at = |az: f32, el: f32, distance: f32| OrbitCamera {
        azimuth_deg: az,
        elevation_deg: el,
        distance,
        ..OrbitCamera::default()
    };
    let scenes = [
        ("param:heart", "param-points", at(30.0, 20.0, 3.0)),
        (
            "param:sh-glyphs:4x4:order8",
            "param-tess",
            at(0.0, 0.0, 1.2),
        ),
        (
            "param:sh-glyphs:4x4:order8",
            "sh-raytrace",
            at(0.0, 0.0, 1.2),
        ),
        ("param:seashell", "param-points", at(30.0, 20.0, 2.0)),
        ("param:yarn:6x8", "param-points", at(0.0, 0.0, 1.3)),
    ];
    let basis = tessera_data::scene::param_spec::default_basis("");
    for (spec, technique, camera) in scenes {
        let started = Instant::now();
        let scene = tessera_data::scene::param_spec::named_scene(spec, basis)?;
        let renderer = match ParamRenderer::new(gpu, compiler, technique, 1, 1, 1) {
            Ok(r) => r,
            Err(e) => {
                println!("skipped {technique}: {e}");
                continue;
            }
        };
        let prepared = renderer.prepare(gpu, &scene)?;
        let size = (args.image_size, args.image_size);
        let (image, gpu_ms) =
            renderer.render_image(gpu, &prepared, &camera, size, [0.1, 0.1, 0.12])?;
        let name = spec.trim_start_matches("param:").replace(':', "-");
        let file = args.out.join(format!("{name}-{technique}.png"));
        crate::output::write_png(&file, &image)?;
        println!(
            "{:<60} {:<20} {:>9.2} ms GPU, {:>8.1} ms with upload",
            file.display(),
            technique,
            gpu_ms,
            started.elapsed().as_secs_f64() * 1e3
        );
    }
    Ok(())
}
