//! `tessera extract`: an isosurface as a PLY mesh in physical units (CPU marching cubes for
//! now, so it takes no device).

use crate::data::{self, IsoArgs, VolumeArgs};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use tessera_data::marching_cubes::marching_cubes_physical;

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
        iso: args.iso.resolve(&volume),
        ..Default::default()
    };
    let iso = look.iso_texel(&volume)?;
    let mesh = marching_cubes_physical(&volume, iso, args.iso.ambiguity);
    crate::output::write_file(&args.output, |w| Ok(mesh.write_ply(w)?))?;
    println!(
        "{}: iso {iso}: {} triangles, {} vertices, area {:.1} (physical units, spacing × index) -> {}",
        volume.name(),
        mesh.triangle_count(),
        mesh.vertex_count(),
        mesh.surface_area(),
        args.output.display()
    );
    Ok(())
}
