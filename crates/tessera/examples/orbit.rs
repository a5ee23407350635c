//! Renders 30 frames of an orbit through the front door for a volume, a tet mesh and a glyph
//! field, changing the isovalue or the transfer-function range every frame, and checks that
//! no frame uploaded data or built pipelines.
//!
//! `cargo run --release -p tessera --example orbit [OUT_DIR]` (OUT_DIR gets every 10th frame
//! as PNG when given).

use std::path::PathBuf;
use tessera::renderer::{self, Frame, RendererOptions, Technique};
use tessera_data::scene::{Appearance, Dataset, IntegrandChoice, LoadOptions};
use tessera_data::transfer::ScalarMode;
use tessera_data::{IsoValue, OrbitCamera, RgbaImage};
use tessera_gpu::{Gpu, GpuOptions};

const FRAMES: u32 = 30;
const SIZE: (u32, u32) = (320, 240);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).map(PathBuf::from);
    let gpu = Gpu::new(&GpuOptions::default())?;
    println!("device: {}", gpu.caps().device_name);
    let scenes = [
        ("procedural:head:96", Technique::Raymarch),
        ("tets:sphere:8", Technique::Interval),
        ("param:sh-glyphs:6x6:order8", Technique::ParamPoints),
    ];
    for (spec, technique) in scenes {
        let data = Dataset::load(spec, &LoadOptions::default())?;
        let mut renderer = renderer::create(&gpu, technique, &RendererOptions::default())?;
        renderer.set_appearance(&gpu, &look(0.0))?;
        renderer.set_data(&gpu, &data)?;
        let before = renderer.counters();
        let mut frame = Frame::new(&gpu, SIZE)?;
        let mut gpu_ms = 0.0;
        for i in 0..FRAMES {
            let t = i as f32 / FRAMES as f32;
            renderer.set_appearance(&gpu, &look(t))?;
            let camera = OrbitCamera {
                azimuth_deg: 360.0 * t,
                elevation_deg: 20.0,
                distance: 1.8,
                ..OrbitCamera::default()
            };
            let view = renderer.view(&camera, SIZE)?;
            gpu_ms += frame.render(&gpu, renderer.as_mut(), &view)?.total_ms();
            if let (Some(dir), 0) = (&out, i % 10) {
                let name = format!("{}-{i:02}.png", technique.name());
                write_png(&dir.join(name), &frame.target.read(&gpu)?)?;
            }
        }
        let after = renderer.counters();
        assert_eq!(
            before, after,
            "{spec}: a new look uploaded data or built pipelines"
        );
        println!(
            "{spec} by {}: {FRAMES} frames, {:.2} ms GPU per frame; {} upload(s) of {} bytes, {} pipeline build(s), none during the orbit",
            technique.name(),
            gpu_ms / f64::from(FRAMES),
            after.data_uploads,
            after.data_bytes,
            after.pipeline_builds
        );
    }
    Ok(())
}

/// The look at orbit time `t` in [0, 1): the isovalue sweeps the head's range, the tet mesh's
/// scalar range narrows.
fn look(t: f32) -> Appearance {
    Appearance {
        iso: IsoValue::Normalized(0.2 + 0.6 * t),
        integrand: IntegrandChoice::Scalar(ScalarMode::Emission),
        range: Some((0.5 * t, 1.0)),
        ..Appearance::default()
    }
}

fn write_png(path: &std::path::Path, image: &RgbaImage) -> Result<(), Box<dyn std::error::Error>> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, image.width, image.height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()?
        .write_image_data(&image.to_rgba_bytes())?;
    Ok(())
}
