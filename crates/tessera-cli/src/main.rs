//! `tessera`: render, measure and export scientific data on the GPU.

mod bench;
mod data;
mod demo;
mod extract;
mod gpu;
mod info;
mod look;
mod output;
mod render;
mod view;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "tessera",
    version,
    about = "GPU rendering of volumes, tetrahedral meshes and glyph fields"
)]
struct Cli {
    /// Vulkan device index (see `tessera info`); default: the first discrete GPU.
    #[arg(long, global = true)]
    device: Option<usize>,
    /// Enable the Khronos validation layer and fail on any error it reports.
    #[arg(long, global = true)]
    validation: bool,
    /// Seconds one batch of GPU work may run before it is given up (a shader that never ends,
    /// e.g. an endless loop in a user function); 0: no limit.
    #[arg(long, global = true, default_value_t = 60.0)]
    gpu_timeout: f64,
    /// Print what the driver reports of each compute pipeline built (registers, shared
    /// memory, instructions; VK_KHR_pipeline_executable_properties), for performance work.
    #[arg(long, global = true)]
    pipeline_stats: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Show devices, drivers, capabilities and the path each technique takes.
    Info(info::InfoArgs),
    /// Render a data set to a PNG.
    #[command(allow_negative_numbers = true)]
    // Boxed: it has far more flags than the other commands.
    Render(Box<render::RenderArgs>),
    /// GPU-timed runs of techniques side by side, as JSON lines.
    #[command(allow_negative_numbers = true)]
    Bench(bench::BenchArgs),
    /// Render a gallery of built-in procedural data sets into a folder.
    Demo(demo::DemoArgs),
    /// Extract an isosurface to a PLY or OBJ mesh in physical units (meshlets on the GPU, or
    /// marching cubes on the CPU).
    #[command(allow_negative_numbers = true)]
    Extract(extract::ExtractArgs),
    /// Open a window on a data set: orbit, edit the look, watch GPU times (or run a script).
    #[command(allow_negative_numbers = true)]
    View(Box<view::ViewArgs>),
}

fn main() {
    let cli = Cli::parse();
    let timeout = match cli.gpu_timeout {
        0.0 => None,
        t => match std::time::Duration::try_from_secs_f64(t) {
            Ok(d) => Some(d),
            Err(_) => {
                eprintln!("error: --gpu-timeout {t}: give seconds (0 = no limit)");
                std::process::exit(2);
            }
        },
    };
    let gpu_options = tessera_gpu::GpuOptions {
        device_index: cli.device,
        validation: cli.validation,
        timeout,
        pipeline_statistics: cli.pipeline_stats,
    };
    let result: Result<()> = match cli.command {
        Command::Info(a) => info::run(&gpu_options, &a),
        Command::Render(a) => render::run(&gpu_options, &a),
        Command::Bench(a) => bench::run(&gpu_options, &a),
        Command::Demo(a) => demo::run(&gpu_options, &a),
        Command::Extract(a) => extract::run(&gpu_options, &a),
        Command::View(a) => view::run(&gpu_options, &a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
