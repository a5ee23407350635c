//! `tessera render`: one image of a data set.

use crate::data::{self, IsoArgs, VolumeArgs};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use tessera::iso::renderer::{IsoRenderer, IsoTechnique};
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct RenderArgs {
    /// A volume file (raw, .nrrd, .nhdr, .nii[.gz]) or procedural:NAME:SIZE[:TYPE], e.g.
    /// procedural:marschner-lobb:128; or a tetrahedral mesh (.vtu, .vtk, .node/.ele, .msh) or
    /// tets:box:N / tets:sphere:N (N³ cells of 6 tets) / tets:asteroids:COUNT (an SDF asteroid
    /// field, one bounding tet per asteroid); or a parametric scene: param:sphere, param:heart,
    /// param:seashell, param:yarn:ROWSxLOOPS[:fibres], param:sh-glyph:orderN, param:sh-glyphs:WxH:orderN (= procedural:sh-glyphs:…), glyphs of
    /// an SH coefficient NIfTI sh:FILE[:zN], or a GLSL file defining `vec3 f(float u, float v)`.
    pub(crate) data: String,
    /// Technique: raymarch or direct for volumes, interval for tetrahedral meshes (the default
    /// follows the data).
    #[arg(long, value_parser = ["raymarch", "direct", "interval", "param-points", "param-tess", "sh-raytrace"])]
    pub(crate) technique: Option<String>,
    #[command(flatten)]
    iso: IsoArgs,
    #[command(flatten)]
    volume: VolumeArgs,
    #[command(flatten)]
    tet: crate::render_tets::TetArgs,
    #[command(flatten)]
    param: crate::render_param::ParamArgs,
    /// Image size WxH.
    #[arg(long, default_value = "1280x720", value_parser = data::parse_size)]
    pub(crate) size: (u32, u32),
    /// Camera AZ,EL,DIST: azimuth and elevation in degrees, distance in units of the volume's longest side.
    #[arg(long, default_value = "30,20,1.8", value_parser = OrbitCamera::parse, allow_hyphen_values = true)]
    pub(crate) camera: OrbitCamera,
    /// Pipeline for techniques that have two: graphics (task/mesh shaders), compute, or auto
    /// (from capabilities and `tessera bench pipeline-throughput` if it ran on this device).
    #[arg(long, default_value = "auto", value_parser = ["graphics", "compute", "auto"])]
    path: String,
    /// Raster occlusion culling for rasterizing techniques (direct).
    #[arg(long, default_value = "on", value_parser = ["on", "off"])]
    culling: String,
    /// Render a stereo pair with this eye separation (world units; the volume's longest side
    /// is 1), left and right eye side by side in one PNG.
    #[arg(long, value_parser = parse_separation)]
    stereo: Option<f32>,
    /// Output PNG.
    #[arg(short, long, default_value = "out.png")]
    pub(crate) output: PathBuf,
}

pub fn run(options: &GpuOptions, args: &RenderArgs) -> Result<()> {
    if crate::render_param::is_param_data(&args.data) {
        return crate::render_param::run(options, args, &args.param);
    }
    if crate::render_tets::is_tet_data(&args.data) {
        return crate::render_tets::run(options, args, &args.tet, &args.path);
    }
    let gpu = crate::open_gpu(options)?;
    if let Some(bytes) = args.volume.expected_bytes(&args.data) {
        gpu.check_fits(&args.data, bytes)
            .with_context(|| format!("{} does not fit on {}", args.data, gpu.caps().device_name))?;
    }
    let volume = data::load(&args.data, &args.volume)?;
    let iso = args.iso.resolve(&volume)?;
    let technique = IsoTechnique::parse(args.technique.as_deref().unwrap_or("raymarch"))?;
    let compiler = tessera::shaders::compiler();
    let started = Instant::now();
    let bar = data::spinner("compiling shaders, uploading, building the min-max octree".into());
    let built = (|| -> tessera::Result<_> {
        let path = tessera::path::PathChoice::parse(&args.path)?;
        let renderer = IsoRenderer::new(&gpu, &compiler, technique, volume.scalar_type(), path)?;
        let prepared = renderer.prepare(&gpu, &volume)?;
        Ok((renderer, prepared))
    })();
    bar.finish_and_clear();
    let (renderer, prepared) = built.with_context(|| format!("preparing {}", args.data))?;
    let prepare_s = started.elapsed().as_secs_f64();
    let (w, h) = args.size;
    let culling = args.culling == "on";
    let frame = match args.stereo {
        None => renderer.render(&gpu, &prepared, iso, &args.camera, args.size, culling)?,
        Some(separation) => {
            let [left, right] = args.camera.stereo_pair(separation);
            let l = renderer.render(&gpu, &prepared, iso, &left, args.size, culling)?;
            let r = renderer.render(&gpu, &prepared, iso, &right, args.size, culling)?;
            tessera::iso::renderer::IsoFrame {
                image: side_by_side(&l.image, &r.image),
                gpu_ms: l.gpu_ms + r.gpu_ms,
                triangles: l.triangles.zip(r.triangles).map(|(a, b)| a + b),
            }
        }
    };
    crate::output::write_png(&args.output, &frame.image)?;
    let triangles = frame
        .triangles
        .map(|t| format!(", {t} triangles"))
        .unwrap_or_default();
    println!(
        "{}: {} ({} path) iso {iso} at {w}x{h}: {:.3} ms GPU{triangles} (prepare {prepare_s:.2} s) -> {}",
        volume.name(),
        technique.name(),
        renderer.path().name(),
        frame.gpu_ms,
        args.output.display()
    );
    crate::check_validation(&gpu)
}

fn side_by_side(left: &RgbaImage, right: &RgbaImage) -> RgbaImage {
    let (w, h) = (left.width, left.height);
    let mut out = RgbaImage::new(2 * w, h);
    let w = w as usize;
    for y in 0..h as usize {
        let dst = &mut out.pixels[y * 2 * w..(y + 1) * 2 * w];
        dst[..w].copy_from_slice(&left.pixels[y * w..(y + 1) * w]);
        dst[w..].copy_from_slice(&right.pixels[y * w..(y + 1) * w]);
    }
    out
}

fn parse_separation(text: &str) -> std::result::Result<f32, String> {
    match text.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("eye separation '{text}' must be a positive number")),
    }
}
