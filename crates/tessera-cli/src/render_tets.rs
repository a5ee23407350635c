//! `tessera render` for tetrahedral meshes: interval shading of a file or a procedural mesh.

use crate::render::RenderArgs;
use anyhow::{bail, Context, Result};
use std::path::Path;
use tessera::tet::interval::{GpuTetMesh, Interval};
use tessera_data::tet::{load_tet_mesh, procedural, TetMesh};
use tessera_gpu::GpuOptions;

/// Light behind the mesh, which absorbs it on the way to the eye.
const BACKLIGHT: [f32; 3] = [1.0, 0.97, 0.9];

const MESH_EXTENSIONS: &[&str] = &["vtu", "vtk", "node", "ele", "msh"];

pub fn is_tet_data(spec: &str) -> bool {
    spec.starts_with("tets:")
        || Path::new(spec)
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| MESH_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

fn load(spec: &str) -> Result<TetMesh> {
    if let Some(rest) = spec.strip_prefix("tets:") {
        let (kind, n) = rest
            .split_once(':')
            .with_context(|| format!("'{spec}': expected tets:box:N or tets:sphere:N"))?;
        let n: u32 = n
            .parse()
            .ok()
            .filter(|&n| (1..=200).contains(&n))
            .with_context(|| format!("'{spec}': N must be a whole number from 1 to 200"))?;
        return match kind {
            "box" => Ok(procedural::box_mesh(n)),
            "sphere" => Ok(procedural::sphere_mesh(n)),
            _ => bail!("'{spec}': unknown mesh '{kind}' (box, sphere)"),
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

pub fn run(options: &GpuOptions, args: &RenderArgs) -> Result<()> {
    match args.technique.as_deref() {
        None | Some("interval") => {}
        Some(t) => bail!(
            "{}: technique '{t}' renders volumes; use --technique interval for tetrahedral meshes",
            args.data
        ),
    }
    let mesh = load(&args.data)?;
    let gpu = crate::open_gpu(options)?;
    let compiler = tessera::shaders::compiler();
    let interval = Interval::new(&gpu, &compiler)?;
    let gpu_mesh = GpuTetMesh::upload(&gpu, &mesh)?;
    let (image, gpu_ms) =
        interval.render_image(&gpu, &gpu_mesh, &args.camera, args.size, BACKLIGHT)?;
    crate::output::write_png(&args.output, &image)?;
    println!(
        "{}: interval, {} tets at {}x{}: {gpu_ms:.3} ms GPU -> {}",
        args.data,
        mesh.tets.len(),
        args.size.0,
        args.size.1,
        args.output.display()
    );
    gpu_mesh.destroy(&gpu);
    interval.destroy(&gpu);
    crate::check_validation(&gpu)
}
