//! `tessera render`: one image of a data set, through the library's front door.

use crate::data::{self, IsoArgs, VolumeArgs};
use crate::look::{self, ParamArgs, PathArgs, ShellArgs, TetArgs};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use tessera::renderer::{self, Frame, Technique};
use tessera::report;
use tessera_data::scene::{Appearance, DataKind, Dataset};
use tessera_data::{OrbitCamera, ViewUp};
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct RenderArgs {
    /// A volume file (raw, .nrrd, .nhdr, .nii[.gz], .vti) or procedural:NAME:SIZE[:TYPE], e.g.
    /// procedural:marschner-lobb:128; or a tetrahedral mesh (.vtu, .vtk, .node/.ele, .msh) or
    /// tets:box:N / tets:sphere:N / tets:ring:N (N³ cells of 6 tets) / tets:asteroids:COUNT (an SDF
    /// asteroid field, one bounding tet per asteroid); or a parametric scene: param:sphere,
    /// param:heart, param:seashell, param:yarn:ROWSxLOOPS[:fibres], param:sh-glyph:orderN,
    /// param:sh-glyphs:WxH:orderN (= procedural:sh-glyphs:…), glyphs of an SH coefficient NIfTI
    /// sh:FILE[:zN], or a GLSL file defining `vec3 f(float u, float v)`.
    pub(crate) data: String,
    /// Technique: raymarch, direct, meshlets (extracted on the GPU, then drawn), offline
    /// (meshoptimizer meshlets of the CPU mesh) or pmb (Parallel Marching Blocks extracted on
    /// the GPU, then drawn; see --pmb-block) for volumes, interval or shell for tetrahedral
    /// meshes, param-points, param-tess or sh-raytrace for parametric objects (the default
    /// follows the data).
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(
        tessera::renderer::Technique::ALL.map(|t| t.name())
    ))]
    pub(crate) technique: Option<String>,
    #[command(flatten)]
    iso: IsoArgs,
    #[command(flatten)]
    volume: VolumeArgs,
    #[command(flatten)]
    tet: TetArgs,
    #[command(flatten)]
    shell: ShellArgs,
    #[command(flatten)]
    param: ParamArgs,
    #[command(flatten)]
    paths: PathArgs,
    /// Image size WxH.
    #[arg(long, default_value = "1280x720", value_parser = data::parse_size)]
    pub(crate) size: (u32, u32),
    /// Camera AZ,EL,DIST: azimuth and elevation in degrees, distance in units of the volume's longest side.
    #[arg(long, default_value = "30,20,1.8", value_parser = OrbitCamera::parse, allow_hyphen_values = true)]
    pub(crate) camera: OrbitCamera,
    /// The axis that appears up: x, y, z, -x, -y or -z (default: towards the head where a
    /// medical file's orientation says, else y). Azimuth turns about it.
    #[arg(long, value_parser = ViewUp::parse, allow_hyphen_values = true)]
    pub(crate) up: Option<ViewUp>,
    /// Render a stereo pair with this eye separation (world units; the volume's longest side
    /// is 1), left and right eye side by side in one PNG.
    #[arg(long, value_parser = parse_separation)]
    stereo: Option<f32>,
    /// Output PNG.
    #[arg(short, long, default_value = "out.png")]
    pub(crate) output: PathBuf,
}

/// What the flags ask to draw, loaded: `render` and `view` start from it.
pub struct Loaded {
    pub technique: Technique,
    pub dataset: Dataset,
    pub look: Appearance,
    pub camera: OrbitCamera,
    pub options: renderer::RendererOptions,
}

/// Loads DATA and turns the flags into a look, camera and renderer options; with `gpu`, a
/// volume that the device cannot hold is refused before its bytes are read.
pub fn load(args: &RenderArgs, gpu: Option<&tessera_gpu::Gpu>) -> Result<Loaded> {
    let kind = DataKind::of_spec(&args.data);
    let technique = Technique::for_data(args.technique.as_deref(), kind, &args.data)?;
    let mut look = look::appearance(&args.iso, &args.tet)?;
    if let (DataKind::Volume, Some(gpu)) = (kind, gpu) {
        data::check_fits(gpu, &args.data, &args.volume)?;
    }
    let dataset = data::load_dataset(&args.data, &look::load_options(&args.volume, &args.param))?;
    let mut camera = args.camera;
    if let Dataset::Volume(volume) = &dataset {
        look.iso = args.iso.resolve(volume);
    }
    camera.up = args.up.unwrap_or_else(|| match dataset.view_up() {
        Some(up) => {
            if up != ViewUp::default() {
                eprintln!(
                    "view up {} (towards the head, from the file's orientation)",
                    up.name()
                );
            }
            up
        }
        None => ViewUp::default(),
    });
    let options = args.shell.apply(
        renderer::RendererOptions {
            layout: args.tet.layout(),
            ..look::renderer_options(&args.paths, &args.param, &args.iso)
        },
        camera.up,
    )?;
    look::warn_ignored(&options, &args.tet, technique);
    Ok(Loaded {
        technique,
        dataset,
        look,
        camera,
        options,
    })
}

pub fn run(options: &GpuOptions, args: &RenderArgs) -> Result<()> {
    let gpu = crate::gpu::open_gpu(options)?;
    let Loaded {
        technique,
        dataset,
        look,
        camera,
        options: renderer_options,
    } = load(args, Some(&gpu))?;
    let started = Instant::now();
    let bar = data::spinner("compiling shaders, uploading, building auxiliary structures".into());
    let built = renderer::create_for(&gpu, technique, &renderer_options, &look, &dataset);
    bar.finish_and_clear();
    let mut renderer =
        built.with_context(|| format!("preparing {} for {}", args.data, technique.name()))?;
    let rendering = || format!("rendering {} with {}", args.data, technique.name());
    let prepare_s = started.elapsed().as_secs_f64();
    let view = renderer.view(&camera, args.size)?;
    let mut frame = Frame::new(&gpu, args.size)?;
    let (image, times) = match args.stereo {
        None => {
            let times = frame
                .render(&gpu, renderer.as_mut(), &view)
                .with_context(rendering)?;
            (frame.target.read(&gpu)?, times)
        }
        Some(separation) => {
            let eyes = view.stereo_pair(separation);
            let mut right = Frame::new(&gpu, args.size)?;
            let times =
                renderer::render_stereo(&gpu, renderer.as_mut(), &eyes, &mut frame, &mut right)
                    .with_context(rendering)?;
            let image = frame
                .target
                .read(&gpu)?
                .side_by_side(&right.target.read(&gpu)?);
            (image, times)
        }
    };
    let gpu_ms = times.total_ms();
    crate::output::write_png(&args.output, &image)?;
    let stats = renderer.stats();
    let triangles = stats
        .triangles
        .map(|t| format!(", {t} triangles"))
        .unwrap_or_default();
    let (w, h) = args.size;
    println!(
        "{}: {} ({} path{}) at {w}x{h}: {gpu_ms:.3} ms GPU{triangles} (prepare {prepare_s:.2} s) -> {}",
        dataset.name(),
        technique.name(),
        renderer.path().name(),
        report::describe(&dataset, &look, technique, &renderer_options),
        args.output.display()
    );
    if technique == Technique::Shell && renderer_options.shell_effects().any() {
        println!("  {}", report::effect_passes(&times, &stats));
    }
    drop(renderer);
    drop(frame);
    crate::gpu::check_validation(&gpu)
}

fn parse_separation(text: &str) -> std::result::Result<f32, String> {
    match text.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("eye separation '{text}' must be a positive number")),
    }
}
