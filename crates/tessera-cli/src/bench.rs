//! `tessera bench`: GPU-timed scenarios, printed as a table and written as JSON lines.

use anyhow::{bail, Context, Result};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use tessera::bench::repeat::{report, spreads};
use tessera::bench::{BenchConfig, BenchRecord, FramePlan, RecordSink, SCENARIOS};
use tessera::path::Path;
use tessera_gpu::GpuOptions;

#[derive(Args)]
pub struct BenchArgs {
    /// pipeline-throughput, raymarch, minmax-build, isosurface (raymarch against direct),
    /// iso-sweep (isovalue changes every frame; meshlets and pmb extract and draw), extraction
    /// (meshlets against PMB at every block size: GPU time and stored bytes), time-varying (a new
    /// volume every frame), stereo (two eyes against one), interval and shell (tet meshes), param
    /// (parametric objects: SH glyphs), growth (every technique's time against pixels and data
    /// size) or all.
    scenario: String,
    /// Append JSON lines here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Timed frames per measurement (after warm-up).
    #[arg(long, default_value_t = 100)]
    frames: u32,
    /// Warm-up frames per measurement at least; more follow until the frame time settles (two
    /// windows of 8 frames agree within 2 %, none 15 % above its median), up to --max-warmup.
    #[arg(long, default_value_t = 10)]
    warmup: u32,
    /// Warm-up frames at most, --min-warmup-ms or not (at or below --warmup, or with --quick:
    /// exactly --warmup); a warm-up that ended here unsettled is marked * in the table.
    #[arg(long, default_value_t = FramePlan::default().max_warmup)]
    max_warmup: u32,
    /// Milliseconds of wall time the warm-up lasts at least.
    #[arg(long, default_value_t = FramePlan::default().min_warmup_ms)]
    min_warmup_ms: u32,
    /// GPU milliseconds each frame plus an arithmetic dispatch after it take, keeping the GPU
    /// loaded between frames as a render loop does, so its clocks stay up; 0: idle gaps.
    #[arg(long, default_value_t = FramePlan::default().keep_busy_ms)]
    keep_busy_ms: f64,
    /// Run the scenarios this many times and list the cells whose stage medians moved by more
    /// than 3 % between runs (every run's records are written, each with its `repeat`).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=10))]
    repeat: u32,
    /// Small volumes and images, for CPU drivers and smoke tests.
    #[arg(long)]
    pub(crate) quick: bool,
    /// Isovalue as a fraction of the value range for the isosurface scenarios.
    #[arg(long, default_value_t = 0.3)]
    pub(crate) iso_fraction: f32,
    /// Benchmark the isosurface scenarios on this volume (a file or procedural:NAME:SIZE[:TYPE])
    /// instead of the built-in head phantoms; or, for `interval` and `shell`, a tet mesh (file
    /// or spec) to measure instead of the procedural meshes.
    #[arg(long)]
    pub(crate) data: Option<String>,
    #[command(flatten)]
    volume: crate::data::VolumeArgs,
    /// Paths for `interval`, `shell`, `extraction`, `param`, `growth`, `isosurface`, `iso-sweep`
    /// (default: every path there; the isosurfaces' reference, ray marching, runs on any).
    #[arg(long, value_delimiter = ',', value_parser = parse_path)]
    pub(crate) paths: Vec<Path>,
    /// Image sizes to measure, in this order (default 1280x720,1920x1080,3840x2160).
    #[arg(long, value_delimiter = ',', value_parser = crate::data::parse_size)]
    pub(crate) sizes: Vec<(u32, u32)>,
    /// `extraction`, `isosurface` also time extractors, direct's rasterizer with stages left out.
    #[arg(long)]
    ablations: bool,
    /// `interval` times only the variants whose label holds this text (e.g. "scalar";
    /// "subgroup" also lists the per-tet pass's ways of drawing with a whole subgroup);
    /// `isosurface`, `iso-sweep`: "hidden-side", "raster-in-extraction" time draws both ways.
    #[arg(long)]
    variants: Option<String>,
    /// `isosurface`, `iso-sweep`: only these techniques (e.g. direct,direct+hzb) and ray marching.
    #[arg(long, value_delimiter = ',')]
    techniques: Vec<String>,
}

fn parse_path(text: &str) -> std::result::Result<Path, String> {
    Path::parse(text).map_err(|e| e.to_string())
}

/// Prints each record as table rows and appends it to the JSON-lines file; keeps the records
/// when the scenarios run more than once.
struct Sink {
    file: Option<(std::fs::File, PathBuf)>,
    /// The run being measured (`--repeat`), from 0.
    repeat: u32,
    kept: Option<Vec<BenchRecord>>,
}

impl RecordSink for Sink {
    fn note(&mut self, text: &str) {
        println!("note: {text}");
    }

    fn emit(&mut self, measured: &BenchRecord) -> tessera::Result<()> {
        let r = &BenchRecord {
            repeat: self.repeat,
            ..measured.clone()
        };
        for s in &r.stages {
            println!(
                "{:<20} {:<10} {:<9} {:<32} {:>5}x{:<5} {:<14} {:>10.3} {:>10.3} {:>10.3} {:>7}",
                r.scenario,
                r.technique,
                r.path,
                r.dataset,
                r.width,
                r.height,
                s.stage,
                s.median_ms,
                s.min_ms,
                s.max_ms,
                format!("{}{}", s.warmup_frames, if s.settled { "" } else { "*" })
            );
        }
        if !r.variant.is_empty() {
            println!("{:<20} variant: {}", "", r.variant);
        }
        if !r.counts.is_empty() {
            let counts: Vec<String> = r
                .counts
                .iter()
                .map(|(k, v)| format!("{k}={v:.4}"))
                .collect();
            println!("{:<20} {}", "", counts.join("  "));
        }
        if let Some((f, path)) = &mut self.file {
            let line = serde_json::to_string(r)
                .map_err(|e| tessera::Error::Invalid(format!("a record as JSON: {e}")))?;
            // Unbuffered: a failing write (a full disk) is reported by this call.
            writeln!(f, "{line}").map_err(|e| {
                tessera::Error::Invalid(format!("writing a record to {}: {e}", path.display()))
            })?;
        }
        if let Some(kept) = &mut self.kept {
            kept.push(r.clone());
        }
        Ok(())
    }
}

pub fn run(options: &GpuOptions, args: &BenchArgs) -> Result<()> {
    let scenarios: Vec<&str> = match args.scenario.as_str() {
        "all" => SCENARIOS.to_vec(),
        s if SCENARIOS.contains(&s) => vec![s],
        s => bail!(
            "unknown scenario '{s}'; choose one of {} or all",
            SCENARIOS.join(", ")
        ),
    };
    let config = BenchConfig {
        plan: FramePlan {
            warmup: args.warmup,
            frames: args.frames.max(1),
            max_warmup: args.max_warmup,
            min_warmup_ms: args.min_warmup_ms,
            keep_busy_ms: args.keep_busy_ms,
            ..FramePlan::default()
        },
        quick: args.quick,
        iso_fraction: args.iso_fraction,
        data: args.data.clone(),
        raw: args.volume.raw_options(),
        paths: args.paths.clone(),
        sizes: args.sizes.clone(),
        ablations: args.ablations,
        variants: args.variants.clone(),
        techniques: args.techniques.clone(),
    };
    tessera::bench::check_options(&scenarios, &config)?;
    let gpu = crate::gpu::open_gpu(options)?;
    let file = match &args.json {
        Some(p) => Some(
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(p)
                .with_context(|| format!("opening {}", p.display()))
                .map(|f| (f, p.clone()))?,
        ),
        None => None,
    };
    let mut sink = Sink {
        file,
        repeat: 0,
        kept: (args.repeat > 1).then(Vec::new),
    };
    let caps = gpu.caps();
    println!(
        "device: {} — {} {}",
        caps.device_name, caps.driver_name, caps.driver_info
    );
    // The column heads of the rows `Sink::emit` prints, laid out at its widths.
    println!("scenario             technique  path      dataset                                 size stage           median ms     min ms     max ms warm-up");
    for repeat in 0..args.repeat {
        if args.repeat > 1 {
            println!("run {} of {}", repeat + 1, args.repeat);
        }
        sink.repeat = repeat;
        for scenario in &scenarios {
            tessera::bench::run(&gpu, scenario, &config, &mut sink)?;
        }
    }
    for line in sink.kept.iter().flat_map(|kept| report(&spreads(kept))) {
        println!("{line}");
    }
    crate::gpu::check_validation(&gpu)
}
