//! `tessera render` for parametric objects (paper E): a named surface, a field of SH glyphs or a
//! user's GLSL function, drawn by param-points, param-tess or (glyphs only) sh-raytrace.

use crate::param_renderer::{ParamRenderer, PreparedScene};
use crate::render::RenderArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use glam::{Mat4, Vec3};
use std::path::Path;
use tessera::param::scene::{ParamObject, ParamScene};
use tessera::param::scenes;
use tessera::param::user::UserFunction;
use tessera::param::{ParamPoints, ParamPointsOptions};
use tessera_data::param::glyph_field::sh_glyph_grid;
use tessera_data::param::{ParamFunction, SeashellParams, ShBasis};
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
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true)]
    u_range: Option<[f32; 2]>,
    /// Parameter range of v for a user function file, like --u-range.
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true)]
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

fn parse_range(text: &str) -> std::result::Result<[f32; 2], String> {
    let (a, b) = text
        .split_once(',')
        .ok_or_else(|| format!("'{text}': expected FROM,TO"))?;
    let end = |t: &str| {
        tessera::param::user::parse_end(t).ok_or_else(|| format!("'{t}' is not a number"))
    };
    Ok([end(a)?, end(b)?])
}

fn parse_order(text: &str, spec: &str) -> Result<u32> {
    text.strip_prefix("order")
        .and_then(|n| n.parse().ok())
        .with_context(|| format!("'{spec}': expected orderN (even N, 2 to 16), found '{text}'"))
}

/// The scene `spec` names: `param:sphere`, `param:heart`, `param:seashell`,
/// `param:yarn:ROWSxLOOPS[:fibres]` (a knitted curtain; 235x254 is the paper's 59,690 yarn
/// curves), `param:sh-glyph:orderN`, or `param:sh-glyphs:WxH:orderN` (also
/// `procedural:sh-glyphs:…`), glyph scenes scaled into the unit box the other data sets are
/// shown in; or `sh:FILE[:zN]`.
pub fn load(spec: &str, basis: ShBasis) -> Result<ParamScene> {
    if let Some(file) = spec.strip_prefix("sh:") {
        return load_coefficients(spec, file, basis);
    }
    let rest = spec
        .strip_prefix("param:")
        .or_else(|| spec.strip_prefix("procedural:"))
        .with_context(|| format!("'{spec}' is not a parametric scene"))?;
    let parts: Vec<&str> = rest.split(':').collect();
    let single = |f: ParamFunction| ParamScene::new(vec![ParamObject::new(f)]);
    match parts[..] {
        ["sphere"] => Ok(single(ParamFunction::Sphere)),
        ["heart"] => Ok(single(ParamFunction::Heart)),
        ["seashell"] => Ok(scenes::seashell(SeashellParams::default())?),
        ["yarn", grid] | ["yarn", grid, "fibres"] => {
            let (rows, loops) = grid
                .split_once('x')
                .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
                .with_context(|| format!("'{spec}': expected ROWSxLOOPS, found '{grid}'"))?;
            Ok(scenes::yarn_curtain(rows, loops, parts.len() == 3)
                .with_context(|| spec.to_string())?)
        }
        ["sh-glyph", order] => {
            let order = parse_order(order, spec)?;
            let field = sh_glyph_grid(1, 1, order, basis, 1).with_context(|| spec.to_string())?;
            Ok(single(ParamFunction::ShGlyph(field[0].glyph.clone())))
        }
        ["sh-glyphs", grid, order] => {
            let (nx, ny) = grid
                .split_once('x')
                .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
                .with_context(|| format!("'{spec}': expected WxH, found '{grid}'"))?;
            let order = parse_order(order, spec)?;
            let field = sh_glyph_grid(nx, ny, order, basis, 1).with_context(|| spec.to_string())?;
            // The grid spans the unit square; glyphs of min-max radius 1 keep a gap.
            Ok(glyph_scene(field, 1.0 / nx.max(ny) as f32))
        }
        _ => bail!(
            "'{spec}': unknown parametric scene (param:sphere, param:heart, param:seashell, \
             param:yarn:ROWSxLOOPS[:fibres], param:sh-glyph:orderN, param:sh-glyphs:WxH:orderN)"
        ),
    }
}

/// Glyphs of an SH coefficient volume: `sh:FILE` (every voxel) or `sh:FILE:zN` (slice N),
/// spaced and sized like the glyph grid, in the unit box.
fn load_coefficients(spec: &str, file: &str, basis: ShBasis) -> Result<ParamScene> {
    let (file, slice) = match file.rsplit_once(":z") {
        Some((f, z)) if z.parse::<u32>().is_ok() => (f, z.parse::<u32>().ok()),
        _ => (file, None),
    };
    let volume = tessera_data::nifti::load_nifti_components(Path::new(file))?;
    let field = tessera_data::param::glyph_field::sh_glyph_volume(&volume, basis, slice, file)
        .with_context(|| spec.to_string())?;
    let spacing = 1.0 / volume.dims.into_iter().max().unwrap_or(1) as f32;
    Ok(glyph_scene(field, spacing))
}

/// Glyphs at their centres times `spacing`, of radius 0.45 spacing (min-max radius 1).
fn glyph_scene(
    field: Vec<tessera_data::param::glyph_field::FieldGlyph>,
    spacing: f32,
) -> ParamScene {
    let objects = field
        .into_iter()
        .map(|g| {
            let to_world = Mat4::from_translation(g.centre * spacing)
                * Mat4::from_scale(Vec3::splat(0.45 * spacing));
            ParamObject::new(ParamFunction::ShGlyph(g.glyph)).with_transform(to_world)
        })
        .collect();
    ParamScene::new(objects)
}

/// The basis named on the command line, or the default for the data: DIPY's legacy
/// descoteaux07 for coefficient files (what its fits write unless told otherwise).
pub fn parse_basis(name: Option<&str>, spec: &str) -> ShBasis {
    let name = name.unwrap_or(if spec.starts_with("sh:") {
        "descoteaux07-legacy"
    } else {
        "descoteaux07"
    });
    match name {
        "tournier07" => ShBasis::Tournier07 { legacy: false },
        "tournier07-legacy" => ShBasis::Tournier07 { legacy: true },
        "descoteaux07-legacy" => ShBasis::Descoteaux07 { legacy: true },
        _ => ShBasis::Descoteaux07 { legacy: false },
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
        f.register(&mut compiler);
        Some(f)
    } else {
        None
    };
    let scene = match &user {
        Some(f) => ParamScene::new(vec![ParamObject::new(ParamFunction::User(f.domain))]),
        None => load(&args.data, parse_basis(param.basis.as_deref(), &args.data))?,
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
        let measured = f.measure_bounds(&gpu, &probe, gpu_scene, 0);
        probe.destroy(&gpu);
        measured?;
    }
    let rendered = renderer.render_image(&gpu, &prepared, &args.camera, args.size, BACKGROUND);
    prepared.destroy(&gpu);
    renderer.destroy(&gpu);
    let (image, gpu_ms) = rendered?;
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
