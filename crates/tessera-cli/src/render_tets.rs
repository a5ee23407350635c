//! `tessera render` for tetrahedral meshes: interval shading of a file or a procedural mesh.

use crate::render::RenderArgs;
use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::Path;
use tessera::path::PathChoice;
use tessera::tet::interval::{self, GpuTetMesh, Integrand, Interval, IntervalOptions};
use tessera_data::scene::parse::{parse_colour, parse_range};
use tessera_data::tet::asteroids::asteroid_field;
use tessera_data::tet::scalar_integral::mapping_range;
use tessera_data::tet::{load_tet_mesh, procedural, TetMesh};
use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction, TABLE_KNOTS};
use tessera_gpu::GpuOptions;

/// Light behind the mesh, which absorbs it on the way to the eye.
const BACKLIGHT: [f32; 3] = [1.0, 0.97, 0.9];
/// Behind emitting meshes and maximum projections.
const DARK: [f32; 3] = [0.02, 0.02, 0.03];

const MESH_EXTENSIONS: &[&str] = &["vtu", "vtk", "node", "ele", "msh"];

/// Options of interval shading.
#[derive(Args)]
pub struct TetArgs {
    /// What rays accumulate through a tet mesh: tet-absorption (per-tet colours, or white),
    /// absorption / emission / mip (the vertex scalars through --tf), or auto (absorption when
    /// the mesh has vertex scalars and no per-tet colours).
    #[arg(long, default_value = "auto", value_parser = ["auto", "tet-absorption", "absorption", "emission", "mip"])]
    integrate: String,
    /// Transfer function for scalar integration: cool-warm, grey, hot, bands, or a file of
    /// 'at r g b a' lines.
    #[arg(long, default_value = "cool-warm")]
    tf: String,
    /// Absorption or emission per unit length at full opacity (the mesh's longest side is 1).
    #[arg(long, default_value_t = 4.0)]
    density: f32,
    /// One absorption colour R,G,B (per unit length) for every tet, in place of the mesh's
    /// per-tet colours (tet-absorption).
    #[arg(long, value_parser = parse_colour)]
    absorption: Option<[f32; 3]>,
    /// Scalar range LO,HI mapped onto the transfer function (default: the mesh's own).
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true)]
    range: Option<(f32, f32)>,
}

pub fn is_tet_data(spec: &str) -> bool {
    spec.starts_with("tets:")
        || Path::new(spec)
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| MESH_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

pub fn load(spec: &str) -> Result<TetMesh> {
    if let Some(rest) = spec.strip_prefix("tets:") {
        let (kind, n) = rest.split_once(':').with_context(|| {
            format!("'{spec}': expected tets:box:N, tets:sphere:N or tets:asteroids:COUNT")
        })?;
        if kind == "asteroids" {
            let count: u32 = n
                .parse()
                .ok()
                .filter(|&n| (1..=4_000_000).contains(&n))
                .with_context(|| format!("'{spec}': COUNT must be from 1 to 4000000"))?;
            return Ok(asteroid_field(count, 1));
        }
        let n: u32 = n
            .parse()
            .ok()
            .filter(|&n| (1..=200).contains(&n))
            .with_context(|| format!("'{spec}': N must be a whole number from 1 to 200"))?;
        return match kind {
            "box" => Ok(procedural::box_mesh(n)),
            "sphere" => Ok(procedural::sphere_mesh(n)),
            _ => bail!("'{spec}': unknown mesh '{kind}' (box, sphere, asteroids)"),
        };
    }
    let (mesh, report) = load_tet_mesh(Path::new(spec))?;
    if report.reoriented + report.degenerate + report.skipped_cells > 0 {
        eprintln!(
            "{spec}: {} inverted tets reoriented, {} degenerate, {} non-tet cells skipped",
            report.reoriented, report.degenerate, report.skipped_cells
        );
    }
    Ok(mesh)
}

/// The integrand the options ask for, with the normalized vertex scalars it needs.
fn integrand(
    spec: &str,
    mesh: &TetMesh,
    args: &TetArgs,
) -> Result<(Integrand, Option<(f32, f32)>)> {
    if spec.starts_with("tets:asteroids:") {
        return Ok((Integrand::Asteroids, None));
    }
    let mode = match args.integrate.as_str() {
        "tet-absorption" => None,
        "auto" if mesh.scalars.is_none() || mesh.absorption.is_some() => None,
        "auto" => Some(ScalarMode::Absorption),
        other => Some(ScalarMode::parse(other)?),
    };
    let Some(mode) = mode else {
        return Ok((Integrand::TetAbsorption, None));
    };
    if !(args.density.is_finite() && args.density > 0.0) {
        bail!("--density must be a positive number, not {}", args.density);
    }
    let range = mapping_range(mesh, args.range, spec)?;
    let tf = TransferFunction::load(&args.tf)?;
    let table = IntegrandTable::new(&tf, mode, args.density, TABLE_KNOTS);
    Ok((Integrand::Scalar { mode, table }, Some(range)))
}

pub fn run(options: &GpuOptions, args: &RenderArgs, tet: &TetArgs, path: &str) -> Result<()> {
    match args.technique.as_deref() {
        None | Some("interval") => {}
        Some(t) => bail!(
            "{}: technique '{t}' renders volumes; use --technique interval for tetrahedral meshes",
            args.data
        ),
    }
    let mut mesh = load(&args.data)?;
    if let Some(colour) = tet.absorption {
        mesh.absorption = Some(vec![colour; mesh.tets.len()]);
    }
    let (integrand, range) = integrand(&args.data, &mesh, tet)?;
    let gpu = crate::open_gpu(options)?;
    let caps = gpu.caps();
    let path = tessera::path::choose_for(
        caps,
        &interval::path_support(caps),
        PathChoice::parse(path)?,
        tessera::path::remembered(caps).as_ref(),
    )?;
    let background = match &integrand {
        Integrand::Scalar {
            mode: ScalarMode::Emission | ScalarMode::Maximum,
            ..
        }
        | Integrand::Asteroids => DARK,
        _ => BACKLIGHT,
    };
    let what = match &integrand {
        Integrand::TetAbsorption => "tet absorption".to_string(),
        Integrand::Asteroids => "sphere-traced asteroids".to_string(),
        Integrand::Scalar { mode, .. } => {
            format!("{mode:?} of '{}'", mesh.scalar_name).to_lowercase()
        }
    };
    let options = IntervalOptions {
        integrand,
        ..IntervalOptions::new(path)
    };
    let compiler = tessera::shaders::compiler();
    let renderer = Interval::new(&gpu, &compiler, &options)?;
    let gpu_mesh = match options.integrand {
        Integrand::Asteroids => GpuTetMesh::upload_asteroids(&gpu, &mesh)?,
        _ => {
            let mut uploaded = GpuTetMesh::upload(&gpu, &mesh)?;
            if let Some(range) = range {
                uploaded.scalar_range = range;
            }
            uploaded
        }
    };
    let (image, gpu_ms) =
        renderer.render_image(&gpu, &gpu_mesh, &args.camera, args.size, background)?;
    crate::output::write_png(&args.output, &image)?;
    println!(
        "{}: interval ({} path, {what}), {} tets at {}x{}: {gpu_ms:.3} ms GPU -> {}",
        args.data,
        path.name(),
        mesh.tets.len(),
        args.size.0,
        args.size.1,
        args.output.display()
    );
    crate::check_validation(&gpu)
}
