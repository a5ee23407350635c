//! `tessera render` for parametric objects (paper E): a named surface or a field of SH glyphs,
//! drawn by the point variant.

use crate::render::RenderArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use glam::{Mat4, Vec3};
use tessera::param::scene::{GpuParamScene, ParamObject, ParamScene};
use tessera::param::{ParamPoints, ParamPointsOptions};
use tessera_data::param::glyph_field::sh_glyph_grid;
use tessera_data::param::{ParamFunction, ShBasis};
use tessera_gpu::GpuOptions;

const BACKGROUND: [f32; 3] = [0.1, 0.1, 0.12];

/// Options of the parametric-object techniques.
#[derive(Args)]
pub struct ParamArgs {
    /// Render at K×K samples per pixel and average (supersampling).
    #[arg(long, default_value_t = 1)]
    supersample: u32,
    /// SH basis of glyphs: descoteaux07 or tournier07 (DIPY's non-legacy forms).
    #[arg(long, default_value = "descoteaux07", value_parser = ["descoteaux07", "tournier07"])]
    basis: String,
}

/// Whether `spec` names a parametric scene.
pub fn is_param_data(spec: &str) -> bool {
    spec.starts_with("param:") || spec.starts_with("procedural:sh-glyphs:")
}

fn parse_order(text: &str, spec: &str) -> Result<u32> {
    text.strip_prefix("order")
        .and_then(|n| n.parse().ok())
        .with_context(|| format!("'{spec}': expected orderN (even N, 2 to 16), found '{text}'"))
}

/// The scene `spec` names: `param:sphere`, `param:heart`, `param:sh-glyph:orderN`, or
/// `param:sh-glyphs:WxH:orderN` (also `procedural:sh-glyphs:…`), scaled into the unit box the
/// other data sets are shown in.
pub fn load(spec: &str, basis: ShBasis) -> Result<ParamScene> {
    let rest = spec
        .strip_prefix("param:")
        .or_else(|| spec.strip_prefix("procedural:"))
        .with_context(|| format!("'{spec}' is not a parametric scene"))?;
    let parts: Vec<&str> = rest.split(':').collect();
    let single = |f: ParamFunction| ParamScene::new(vec![ParamObject::new(f)]);
    match parts[..] {
        ["sphere"] => Ok(single(ParamFunction::Sphere)),
        ["heart"] => Ok(single(ParamFunction::Heart)),
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
            let spacing = 1.0 / nx.max(ny) as f32;
            let objects = field
                .into_iter()
                .map(|g| {
                    let to_world = Mat4::from_translation(g.centre * spacing)
                        * Mat4::from_scale(Vec3::splat(0.45 * spacing));
                    ParamObject::new(ParamFunction::ShGlyph(g.glyph)).with_transform(to_world)
                })
                .collect();
            Ok(ParamScene::new(objects))
        }
        _ => bail!(
            "'{spec}': unknown parametric scene (param:sphere, param:heart, param:sh-glyph:orderN, \
             param:sh-glyphs:WxH:orderN)"
        ),
    }
}

pub fn parse_basis(name: &str) -> ShBasis {
    match name {
        "tournier07" => ShBasis::Tournier07 { legacy: false },
        _ => ShBasis::Descoteaux07 { legacy: false },
    }
}

pub fn run(options: &GpuOptions, args: &RenderArgs, param: &ParamArgs) -> Result<()> {
    match args.technique.as_deref() {
        None | Some("param-points") => {}
        Some(t) => bail!(
            "{}: technique '{t}' does not draw parametric objects; use --technique param-points",
            args.data
        ),
    }
    if !(1..=8).contains(&param.supersample) {
        bail!("--supersample must be 1 to 8, not {}", param.supersample);
    }
    let scene = load(&args.data, parse_basis(&param.basis))?;
    let gpu = crate::open_gpu(options)?;
    let compiler = tessera::shaders::compiler();
    let points_options = ParamPointsOptions {
        supersample: param.supersample,
        ..ParamPointsOptions::default()
    };
    let renderer = ParamPoints::new(&gpu, &compiler, points_options)?;
    let gpu_scene = GpuParamScene::upload(&gpu, &scene)?;
    let rendered = renderer.render_image(&gpu, &gpu_scene, &args.camera, args.size, BACKGROUND);
    gpu_scene.destroy(&gpu);
    renderer.destroy(&gpu);
    let (image, gpu_ms) = rendered?;
    crate::output::write_png(&args.output, &image)?;
    println!(
        "{}: param-points, {} objects at {}x{}: {gpu_ms:.3} ms GPU -> {}",
        args.data,
        scene.objects.len(),
        args.size.0,
        args.size.1,
        args.output.display()
    );
    crate::check_validation(&gpu)
}
