//! `tessera extract`: an isosurface as a welded PLY or OBJ mesh in physical units, and
//! optionally its meshlets, by paper C's GPU meshlet extraction or CPU marching cubes.

use crate::data::{self, IsoArgs, VolumeArgs};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use tessera::iso::surface::{extract_surface, Surface, SurfaceMethod};
use tessera_data::mesh::MeshFormat;
use tessera_data::meshlets::{write_meshlet_file, MeshletFile, MeshletUnits};
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct ExtractArgs {
    /// A volume file or procedural:NAME:SIZE[:TYPE].
    data: String,
    #[command(flatten)]
    iso: IsoArgs,
    #[command(flatten)]
    volume: VolumeArgs,
    /// Output mesh, welded and indexed: .ply (binary) or .obj; binary PLY for a name without
    /// an extension.
    #[arg(short, long, default_value = "surface.ply")]
    output: PathBuf,
    /// Extractor: meshlets (paper C's meshlet extraction on the GPU), pmb or pmb:XxYxZ
    /// (Parallel Marching Blocks on the GPU; blocks of 4x4x4, 8x4x4, 8x8x4 (pmb) or 8x8x8
    /// cells) or cpu (single-threaded marching cubes). All give the same triangles.
    #[arg(long, default_value = "meshlets")]
    method: String,
    /// Pipeline of the meshlet extraction: compute, mesh (the paper's task and mesh shaders)
    /// or auto (compute: the same meshlets on every device).
    #[arg(long, default_value = "auto")]
    path: String,
    /// Also write the meshlets (descriptors with bounds, positions, normals, 8-bit local
    /// indices) to this file, in the binary layout `tessera_data::meshlets::file` documents.
    #[arg(long)]
    meshlets: Option<PathBuf>,
}

pub fn run(options: &GpuOptions, args: &ExtractArgs) -> Result<()> {
    let method = SurfaceMethod::parse(&args.method, &args.path)?;
    // A name without an extension (a device such as /dev/stdout) gets the default PLY.
    let format = match args.output.extension() {
        None => MeshFormat::Ply,
        Some(_) => MeshFormat::from_path(&args.output)?,
    };
    if args.meshlets.is_some() && !matches!(method, SurfaceMethod::Meshlets(_)) {
        anyhow::bail!(
            "--meshlets needs --method meshlets: {} makes none",
            method.describe()
        );
    }
    if !method.needs_gpu() && (options.device_index.is_some() || options.validation) {
        anyhow::bail!(
            "extract --method cpu runs on the CPU (marching cubes): --device and --validation \
             do not apply"
        );
    }
    let volume = data::load(&args.data, &args.volume)?;
    let look = tessera_data::scene::Appearance {
        iso: args.iso.resolve(&volume),
        ..Default::default()
    };
    let iso = look.iso_texel(&volume)?;
    let gpu = if method.needs_gpu() {
        Some(crate::gpu::open_gpu(options).with_context(|| {
            format!(
                "{} needs a Vulkan device (--method cpu does not)",
                method.describe()
            )
        })?)
    } else {
        None
    };
    let surface = extract_surface(gpu.as_ref(), &volume, iso, args.iso.ambiguity, method)?
        .transformed(&volume.grid_to_physical());
    if let Some(gpu) = &gpu {
        crate::gpu::check_validation(gpu)?;
    }
    crate::output::write_file(&args.output, |w| Ok(surface.mesh.write_as(format, w)?))?;
    if let (Some(path), Some(meshlets)) = (&args.meshlets, &surface.meshlets) {
        let file = MeshletFile {
            mesh: meshlets.clone(),
            isovalue: iso,
            units: MeshletUnits::Physical,
        };
        crate::output::write_file(path, |w| Ok(write_meshlet_file(&file, w)?))?;
    }
    println!("{}", summary(volume.name(), iso, method, &surface, args));
    Ok(())
}

fn summary(name: &str, iso: f32, method: SurfaceMethod, s: &Surface, args: &ExtractArgs) -> String {
    let mesh = &s.mesh;
    let cost = &s.cost;
    let mut text = format!(
        "{name}: iso {iso}: {} triangles, {} vertices, area {:.1} (physical units, spacing × \
         index)",
        mesh.triangle_count(),
        mesh.vertex_count(),
        mesh.surface_area(),
    );
    if let Some(m) = &s.meshlets {
        text += &format!(
            "; {} meshlets ({} vertices before welding)",
            m.meshlets.len(),
            m.vertex_count()
        );
    }
    if method.needs_gpu() {
        text += &format!(
            "; {}: extracted in {:.3} ms GPU time ({} attempt{}), {:.2} MB stored, upload and \
             min-max octree {:.1} ms",
            method.describe(),
            cost.extract_ms,
            cost.attempts,
            if cost.attempts == 1 { "" } else { "s" },
            cost.stored_bytes as f64 / 1e6,
            cost.prepare_ms,
        );
    } else {
        text += &format!(
            "; {}: extracted in {:.1} ms",
            method.describe(),
            cost.extract_ms
        );
    }
    text += &format!(" -> {}", args.output.display());
    if let Some(path) = &args.meshlets {
        text += &format!(", {}", path.display());
    }
    text
}
