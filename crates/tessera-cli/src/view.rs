//! `tessera view`: the interactive viewer (crate `tessera-view`) over what `render` loads.

use crate::render::{self, RenderArgs};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct ViewArgs {
    /// The options of `render`; --size is the window's, --output the default screenshot name.
    #[command(flatten)]
    render: RenderArgs,
    /// Run the steps of this script file (camera, iso, tf, screenshot, resize, …; see the
    /// README's Viewer section) and exit, with no one at the controls.
    #[arg(long)]
    script: Option<PathBuf>,
    /// Render every frame, not only when something changed (to watch the frame time).
    #[arg(long)]
    continuous: bool,
    /// Run the script without a window (no display needed) and report the GPU frame times.
    #[arg(long, requires = "script")]
    offscreen: bool,
}

pub fn run(gpu: &GpuOptions, args: &ViewArgs) -> Result<()> {
    if !args.offscreen {
        tessera_view::check_display()?;
    }
    let script = match &args.script {
        Some(path) => Some(tessera_view::Script::load(path)?),
        None => None,
    };
    let loaded = render::load(&args.render, None)?;
    let scene = tessera_view::Scene {
        name: args.render.data.clone(),
        technique: loaded.technique,
        dataset: loaded.dataset,
        look: loaded.look,
        camera: loaded.camera,
        options: loaded.options,
    };
    let settings = tessera_view::Settings {
        gpu: gpu.clone(),
        size: args.render.size,
        screenshot: args.render.output.clone(),
        script,
        continuous: args.continuous,
    };
    let summary = match args.offscreen {
        true => tessera_view::run_offscreen(scene, settings),
        false => tessera_view::run(scene, settings),
    }
    .context("tessera view")?;
    println!("{summary}");
    Ok(())
}
