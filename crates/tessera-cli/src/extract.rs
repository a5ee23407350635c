//! `tessera extract`: an isosurface as a PLY mesh (CPU marching cubes for now).

use crate::data::{self, IsoArgs, VolumeArgs};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use tessera_data::marching_cubes::marching_cubes;

#[derive(Args)]
pub struct ExtractArgs {
    /// A volume file or procedural:NAME:SIZE[:TYPE].
    data: String,
    #[command(flatten)]
    iso: IsoArgs,
    #[command(flatten)]
    volume: VolumeArgs,
    /// Output PLY.
    #[arg(short, long, default_value = "surface.ply")]
    output: PathBuf,
}

pub fn run(args: &ExtractArgs) -> Result<()> {
    let volume = data::load(&args.data, &args.volume)?;
    let look = tessera_data::scene::Appearance {
        iso: args.iso.value(),
        ..Default::default()
    };
    let iso = look.iso_texel(&volume)?;
    let mesh = marching_cubes(&volume, iso);
    let file = std::fs::File::create(&args.output)
        .with_context(|| format!("creating {}", args.output.display()))?;
    let mut w = std::io::BufWriter::new(file);
    mesh.write_ply(&mut w)
        .with_context(|| format!("writing {}", args.output.display()))?;
    println!(
        "{}: iso {iso}: {} triangles, {} vertices, area {:.1} (grid units) -> {}",
        volume.name(),
        mesh.triangle_count(),
        mesh.vertex_count(),
        mesh.surface_area(),
        args.output.display()
    );
    Ok(())
}
