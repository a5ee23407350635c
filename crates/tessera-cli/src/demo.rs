//! `tessera demo`: a gallery from built-in procedural data, no files needed, every image drawn
//! through the library's front door.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use tessera::path::PathChoice;
use tessera::renderer::{self, RendererOptions, Technique};
use tessera_data::scene::{Appearance, Dataset, IntegrandChoice, LoadOptions};
use tessera_data::transfer::{ScalarMode, TransferFunction};
use tessera_data::{IsoValue, OrbitCamera};
use tessera_gpu::{Gpu, GpuOptions};

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

/// One image of the gallery.
struct Scene {
    spec: String,
    technique: Technique,
    path: PathChoice,
    look: Appearance,
    camera: OrbitCamera,
    /// The PNG's name without extension; `{name}` stands for the data set's name and
    /// `{tets}` for a mesh's tet count.
    file: String,
}

fn camera(azimuth_deg: f32, elevation_deg: f32, distance: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg,
        elevation_deg,
        distance,
        ..OrbitCamera::default()
    }
}

fn iso(fraction: f32) -> Appearance {
    Appearance {
        iso: IsoValue::Normalized(fraction),
        ..Appearance::default()
    }
}

/// Isosurfaces of the procedural volumes.
fn volume_scenes(size: u32) -> Vec<Scene> {
    [
        (Technique::Raymarch, "sphere", "uint8", 0.7, (30.0, 20.0)),
        (
            Technique::Raymarch,
            "marschner-lobb",
            "uint16",
            0.5,
            (20.0, 35.0),
        ),
        (Technique::Raymarch, "head", "uint8", 0.2, (40.0, 15.0)),
        (Technique::Raymarch, "head", "uint8", 0.8, (40.0, 15.0)),
        (
            Technique::Raymarch,
            "turbulence",
            "float32",
            0.55,
            (25.0, 30.0),
        ),
        (
            Technique::Direct,
            "marschner-lobb",
            "uint16",
            0.5,
            (20.0, 35.0),
        ),
        (
            Technique::Direct,
            "turbulence",
            "float32",
            0.55,
            (25.0, 30.0),
        ),
    ]
    .into_iter()
    .map(|(technique, kind, scalar, fraction, (az, el))| Scene {
        file: format!("{}-{{name}}-iso{fraction:.2}", technique.name()),
        spec: format!("procedural:{kind}:{size}:{scalar}"),
        technique,
        path: PathChoice::Auto,
        look: iso(fraction),
        camera: camera(az, el, 1.9),
    })
    .collect()
}

/// A tetrahedral sphere with per-tet absorption colours seen against a light, and its radius
/// field through a transfer function as emission, then paper A's asteroid field, each on both
/// paths.
fn interval_scenes(size: u32) -> Result<Vec<Scene>> {
    let cells = (size / 8).max(2);
    let emission = Appearance {
        integrand: IntegrandChoice::Scalar(ScalarMode::Emission),
        transfer: TransferFunction::preset("hot")?,
        density: 3.0,
        ..Appearance::default()
    };
    let absorption = Appearance {
        integrand: IntegrandChoice::TetAbsorption,
        ..Appearance::default()
    };
    let asteroids = Appearance {
        background: Some([0.02; 3]),
        ..Appearance::default()
    };
    let mut scenes = Vec::new();
    for path in [PathChoice::Graphics, PathChoice::Compute] {
        let name = if path == PathChoice::Graphics {
            "graphics"
        } else {
            "compute"
        };
        for (what, look) in [("absorption", &absorption), ("emission", &emission)] {
            scenes.push(Scene {
                spec: format!("tets:sphere:{cells}"),
                technique: Technique::Interval,
                path,
                look: look.clone(),
                camera: camera(30.0, 20.0, 2.2),
                file: format!("interval-sphere-{{tets}}tets-{what}-{name}"),
            });
        }
        scenes.push(Scene {
            spec: "tets:asteroids:200".into(),
            technique: Technique::Interval,
            path,
            look: asteroids.clone(),
            camera: camera(30.0, 20.0, 1.5),
            file: format!("asteroids-200-{name}"),
        });
    }
    Ok(scenes)
}

/// Paper E's parametric objects: a heart by points, SH glyphs by tessellation and by ray
/// tracing, a seashell and a knitted curtain.
fn parametric_scenes() -> Vec<Scene> {
    [
        (
            "param:heart",
            Technique::ParamPoints,
            camera(30.0, 20.0, 3.0),
        ),
        (
            "param:sh-glyphs:4x4:order8",
            Technique::ParamTess,
            camera(0.0, 0.0, 1.2),
        ),
        (
            "param:sh-glyphs:4x4:order8",
            Technique::ShRaytrace,
            camera(0.0, 0.0, 1.2),
        ),
        (
            "param:seashell",
            Technique::ParamPoints,
            camera(30.0, 20.0, 2.0),
        ),
        (
            "param:yarn:6x8",
            Technique::ParamPoints,
            camera(0.0, 0.0, 1.3),
        ),
    ]
    .into_iter()
    .map(|(spec, technique, camera)| Scene {
        file: format!(
            "{}-{}",
            spec.trim_start_matches("param:").replace(':', "-"),
            technique.name()
        ),
        spec: spec.into(),
        technique,
        path: PathChoice::Auto,
        look: Appearance::default(),
        camera,
    })
    .collect()
}

pub fn run(options: &GpuOptions, args: &DemoArgs) -> Result<()> {
    let gpu = crate::gpu::open_gpu(options)?;
    println!(
        "device: {} ({})",
        gpu.caps().device_name,
        gpu.caps().driver_info
    );
    let mut scenes = volume_scenes(args.volume_size);
    scenes.extend(interval_scenes(args.volume_size)?);
    scenes.extend(parametric_scenes());
    for (index, scene) in scenes.iter().enumerate() {
        let progress = format!("[{}/{}]", index + 1, scenes.len());
        render_scene(&gpu, scene, args, &progress)?;
    }
    crate::gpu::check_validation(&gpu)
}

/// Renders one scene and reports its GPU time and its time with loading, uploads and
/// auxiliary structures; a technique the device cannot run is reported as skipped.
fn render_scene(gpu: &Gpu, scene: &Scene, args: &DemoArgs, progress: &str) -> Result<()> {
    let started = Instant::now();
    let data = Dataset::load(&scene.spec, &LoadOptions::default())?;
    let options = RendererOptions {
        path: scene.path,
        ..RendererOptions::default()
    };
    let prepared = renderer::create(gpu, scene.technique, &options).and_then(|mut r| {
        r.set_appearance(gpu, &scene.look)?;
        r.set_data(gpu, &data)?;
        Ok(r)
    });
    let mut renderer = match prepared {
        Ok(r) => r,
        Err(e) => {
            println!(
                "{progress} skipped {} on {}: {e}",
                scene.technique.name(),
                scene.spec
            );
            return Ok(());
        }
    };
    let size = (args.image_size, args.image_size);
    let rendered = renderer::render_image(gpu, renderer.as_mut(), &scene.camera, size)?;
    let tets = match &data {
        Dataset::Tets(t) => t.mesh.tets.len(),
        _ => 0,
    };
    let name = scene
        .file
        .replace("{name}", data.name())
        .replace("{tets}", &tets.to_string());
    let file = args.out.join(format!("{name}.png"));
    crate::output::write_png(&file, &rendered.image)?;
    let label = format!("{} ({})", scene.technique.name(), renderer.path().name());
    println!(
        "{progress:<7} {:<60} {label:<24} {:>9.2} ms GPU, {:>8.1} ms with loading and uploads",
        file.display(),
        rendered.times.total_ms(),
        started.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}
