//! `tessera render` for parametric objects (paper E): a named surface, a field of SH glyphs or a
//! user's GLSL function, drawn by param-points, param-tess or (glyphs only) sh-raytrace.

use crate::param_renderer::{ParamRenderer, PreparedScene};
use crate::render::RenderArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::Path;
use tessera::param::scene::{ParamObject, ParamScene};
use tessera::param::user::UserFunction;
use tessera::param::{ParamPoints, ParamPointsOptions};
use tessera_data::param::{ParamFunction, ShBasis};
use tessera_data::scene::param_spec::{default_basis, named_scene};
use tessera_data::scene::parse::{parse_basis, parse_param_range};
use tessera_gpu::GpuOptions;

const BACKGROUND: [f32; 3] = [0.1, 0.1, 0.12];

/// Options of the parametric-object techniques.
#[derive(Args)]
pub struct ParamArgs {
    /// Render at K×K samples per pixel and average (supersampling).
    #[arg(long, default_value_t = 1)]
    supersample: u32,
    /// Start each object as K×K patches (a power of two up to 16) before the LOD stage.
    #[arg(long, default_value_t = 1)]
    pre_split: u32,
    /// Multisampling of param-tess: 1, 2, 4 or 8 samples per pixel.
    #[arg(long, default_value_t = 1)]
    msaa: u32,
    /// Parameter range FROM,TO of u for a user function file (numbers, or multiples of pi/tau:
    /// 0,2pi); overrides the file's '// u: FROM TO' line.
    #[arg(long, value_parser = parse_param_range, allow_hyphen_values = true)]
    u_range: Option<[f32; 2]>,
    /// Parameter range of v for a user function file, like --u-range.
    #[arg(long, value_parser = parse_param_range, allow_hyphen_values = true)]
    v_range: Option<[f32; 2]>,
    /// SH basis of glyphs: descoteaux07 or tournier07, each also -legacy (DIPY's `legacy=True`).
    /// Default: descoteaux07-legacy for coefficient files (DIPY's default), descoteaux07 else.
    #[arg(long, value_parser = ["descoteaux07", "descoteaux07-legacy", "tournier07", "tournier07-legacy"])]
    basis: Option<String>,
}

/// Whether `spec` names a parametric scene (or a GLSL file of a user function).
pub fn is_param_data(spec: &str) -> bool {
    spec.starts_with("param:")
        || spec.starts_with("sh:")
        || spec.starts_with("procedural:sh-glyphs:")
        || spec.to_ascii_lowercase().ends_with(".glsl")
}

/// The basis named on the command line, or the default for the data
/// ([`tessera_data::scene::param_spec::default_basis`]).
pub fn basis_of(name: Option<&str>, spec: &str) -> Result<ShBasis> {
    match name {
        Some(name) => parse_basis(name).map_err(anyhow::Error::msg),
        None => Ok(default_basis(spec)),
    }
}

pub fn run(options: &GpuOptions, args: &RenderArgs, param: &ParamArgs) -> Result<()> {
    let technique = match args.technique.as_deref() {
        None | Some("param-points") => "param-points",
        Some("param-tess") => "param-tess",
        Some("sh-raytrace") => "sh-raytrace",
        Some(t) => bail!(
            "{}: technique '{t}' does not draw parametric objects; use --technique param-points, \
             param-tess or sh-raytrace",
            args.data
        ),
    };
    if !(1..=8).contains(&param.supersample) {
        bail!("--supersample must be 1 to 8, not {}", param.supersample);
    }
    let mut compiler = tessera::shaders::compiler();
    let user = if args.data.to_ascii_lowercase().ends_with(".glsl") {
        let f = UserFunction::load(Path::new(&args.data), param.u_range, param.v_range)?;
        tessera::param::user::register_user_function(&f, &mut compiler);
        Some(f)
    } else {
        None
    };
    let scene = match &user {
        Some(f) => ParamScene::new(vec![ParamObject::new(ParamFunction::User(f.domain))]),
        None => named_scene(&args.data, basis_of(param.basis.as_deref(), &args.data)?)?,
    };
    let gpu = crate::open_gpu(options)?;
    let renderer = ParamRenderer::new(
        &gpu,
        &compiler,
        technique,
        param.supersample,
        param.msaa,
        param.pre_split,
    )?;
    let mut prepared = renderer
        .prepare(&gpu, &scene)
        .with_context(|| args.data.clone())?;
    if let (Some(f), PreparedScene::Plain(gpu_scene)) = (&user, &mut prepared) {
        // The CPU cannot evaluate the user's GLSL: its extent is measured on the GPU.
        let probe = ParamPoints::new(&gpu, &compiler, ParamPointsOptions::default())?;
        tessera::param::user::measure_bounds(f, &gpu, &probe, gpu_scene, 0)?;
    }
    let (image, gpu_ms) =
        renderer.render_image(&gpu, &prepared, &args.camera, args.size, BACKGROUND)?;
    crate::output::write_png(&args.output, &image)?;
    println!(
        "{}: {technique}, {} objects at {}x{}: {gpu_ms:.3} ms GPU -> {}",
        args.data,
        scene.objects.len(),
        args.size.0,
        args.size.1,
        args.output.display()
    );
    crate::check_validation(&gpu)
}
