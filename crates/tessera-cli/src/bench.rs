//! `tessera bench`: GPU-timed scenarios, printed as a table and written as JSON lines.

use anyhow::{bail, Context, Result};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use tessera::bench::{time_frames, BenchRecord, FramePlan};
use tessera::iso::raymarch::Raymarch;
use tessera::target::Target;
use tessera_data::minmax::MinMaxOctree;
use tessera_data::scene::DataKind;
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};
use tessera_gpu::{vk, Gpu, GpuOptions, MemoryLocation};

const SCENARIOS: &[&str] = &[
    "pipeline-throughput",
    "raymarch",
    "minmax-build",
    "isosurface",
    "iso-sweep",
    "time-varying",
    "stereo",
    "interval",
    "param",
];

#[derive(Args)]
pub struct BenchArgs {
    /// pipeline-throughput, raymarch, minmax-build, isosurface (raymarch against direct),
    /// iso-sweep (isovalue changes every frame), time-varying (a new volume every frame),
    /// stereo (two eyes against one), interval (tet meshes), param (parametric objects: SH
    /// glyphs) or all.
    scenario: String,
    /// Append JSON lines here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Timed frames per measurement (after warm-up).
    #[arg(long, default_value_t = 100)]
    frames: u32,
    #[arg(long, default_value_t = 10)]
    warmup: u32,
    /// Small volumes and images, for CPU drivers and smoke tests.
    #[arg(long)]
    pub(crate) quick: bool,
    /// Isovalue as a fraction of the value range for the isosurface scenarios.
    #[arg(long, default_value_t = 0.3)]
    pub(crate) iso_fraction: f32,
    /// Benchmark the isosurface scenarios on this volume (a file or procedural:NAME:SIZE[:TYPE])
    /// instead of the built-in head phantoms; or, for `interval`, a tet mesh file to add to the
    /// procedural meshes.
    #[arg(long)]
    pub(crate) data: Option<String>,
    #[command(flatten)]
    volume: crate::data::VolumeArgs,
    /// Paths to measure for `interval` (default: every path the device has).
    #[arg(long, value_delimiter = ',', value_parser = ["graphics", "compute"])]
    pub(crate) paths: Vec<String>,
    /// Image sizes to measure, in this order (default 1280x720,1920x1080,3840x2160).
    #[arg(long, value_delimiter = ',', value_parser = crate::data::parse_size)]
    pub(crate) sizes: Vec<(u32, u32)>,
}

pub(crate) struct Sink {
    file: Option<std::fs::File>,
}

impl Sink {
    pub(crate) fn emit(&mut self, r: &BenchRecord) -> Result<()> {
        for s in &r.stages {
            println!(
                "{:<20} {:<10} {:<9} {:<32} {:>5}x{:<5} {:<14} {:>10.3} {:>10.3} {:>10.3}",
                r.scenario,
                r.technique,
                r.path,
                r.dataset,
                r.width,
                r.height,
                s.stage,
                s.median_ms,
                s.min_ms,
                s.max_ms
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
        if let Some(f) = &mut self.file {
            writeln!(f, "{}", serde_json::to_string(r)?)?;
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
    let gpu = crate::open_gpu(options)?;
    let file = match &args.json {
        Some(p) => Some(
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(p)
                .with_context(|| format!("opening {}", p.display()))?,
        ),
        None => None,
    };
    let mut sink = Sink { file };
    let caps = gpu.caps();
    println!(
        "device: {} — {} {}",
        caps.device_name, caps.driver_name, caps.driver_info
    );
    println!(
        "{:<20} {:<10} {:<9} {:<32} {:>11} {:<14} {:>10} {:>10} {:>10}",
        "scenario",
        "technique",
        "path",
        "dataset",
        "size",
        "stage",
        "median ms",
        "min ms",
        "max ms"
    );
    let plan = FramePlan {
        warmup: args.warmup,
        frames: args.frames.max(1),
    };
    for scenario in scenarios {
        match scenario {
            "pipeline-throughput" => throughput(&gpu, args, plan, &mut sink)?,
            "raymarch" => raymarch(&gpu, args, plan, &mut sink)?,
            "minmax-build" => minmax_build(&gpu, args, plan, &mut sink)?,
            "isosurface" => crate::bench_iso::isosurface(&gpu, args, plan, &mut sink)?,
            "iso-sweep" => crate::bench_iso::iso_sweep(&gpu, args, plan, &mut sink)?,
            "time-varying" => crate::bench_iso::time_varying(&gpu, args, plan, &mut sink)?,
            "stereo" => crate::bench_stereo::stereo(&gpu, args, plan, &mut sink)?,
            "interval" => crate::bench_tet::interval(&gpu, args, plan, &mut sink)?,
            "param" => crate::bench_param::param(&gpu, args, plan, &mut sink)?,
            _ => unreachable!("scenario list checked above"),
        }
    }
    crate::check_validation(&gpu)
}

fn throughput(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    let compiler = tessera::shaders::compiler();
    let mut opts = tessera::throughput::ThroughputOptions {
        plan,
        ..Default::default()
    };
    if args.quick {
        opts.width = 256;
        opts.height = 144;
        opts.triangles = 20_000;
        opts.iterations = 16;
    }
    for note in tessera::throughput::notes(gpu) {
        println!("note: {note}");
    }
    let records = tessera::throughput::run(gpu, &compiler, &opts)?;
    for r in &records {
        sink.emit(r)?;
    }
    for (what, ratio) in tessera::throughput::summarize(&records) {
        println!(
            "{:<20} {what}: graphics path {ratio:.2}x the compute time",
            ""
        );
    }
    Ok(())
}

/// The volumes of the isosurface scenarios: `--data`, or head-like phantoms of DESIGN §6's sizes.
pub(crate) fn bench_volumes(args: &BenchArgs) -> Vec<String> {
    if let Some(data) = args
        .data
        .as_ref()
        .filter(|d| DataKind::of_spec(d) == DataKind::Volume)
    {
        return vec![data.clone()];
    }
    let sizes: &[(u32, ScalarType)] = if args.quick {
        &[(64, ScalarType::U8), (96, ScalarType::U16)]
    } else {
        &[
            (256, ScalarType::U8),
            (512, ScalarType::U8),
            (1024, ScalarType::U16),
        ]
    };
    sizes
        .iter()
        .map(|(size, scalar)| format!("procedural:head:{size}:{}", scalar.name()))
        .collect()
}

pub(crate) fn bench_sizes(args: &BenchArgs) -> Vec<(u32, u32)> {
    if !args.sizes.is_empty() {
        return args.sizes.clone();
    }
    if args.quick {
        vec![(256, 144)]
    } else {
        vec![(1280, 720), (1920, 1080), (3840, 2160)]
    }
}

/// Renders for a while right after a volume arrives on the GPU. Measured on the H200: with
/// only the per-measurement warm-up, the first size timed after uploading a 2 GiB volume came
/// out 2–4× slower than the same size timed later (docs/BENCHMARKS.md, run 16).
pub(crate) fn settle(
    gpu: &Gpu,
    raymarch: &Raymarch,
    prepared: &tessera::iso::PreparedVolume,
    iso: f32,
) -> Result<()> {
    const SETTLE_FRAMES: u32 = 100;
    let target = Target::new(gpu, 1280, 720)?;
    let params = Raymarch::params(prepared, iso, &OrbitCamera::default(), 1280, 720);
    let result = gpu.submit("settle", |rec| {
        for _ in 0..SETTLE_FRAMES {
            raymarch.record(rec, prepared, &target, &params);
        }
    });
    Ok(result?)
}

pub(crate) fn make_volume(gpu: &Gpu, spec: &str, args: &BenchArgs) -> Result<Volume> {
    crate::data::check_fits(gpu, spec, &args.volume)?;
    crate::data::load(spec, &args.volume)
}

fn raymarch(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    let compiler = tessera::shaders::compiler();
    let camera = OrbitCamera::default();
    for spec in bench_volumes(args) {
        let volume = make_volume(gpu, &spec, args)?;
        let scalar = volume.scalar_type();
        let iso = volume.iso_to_texel(IsoValue::Normalized(args.iso_fraction));
        let occupied = MinMaxOctree::build(&volume).occupied_fraction(iso);
        let rm = Raymarch::new(gpu, &compiler, scalar)?;
        let prepared = rm.prepare(gpu, &volume)?;
        settle(gpu, &rm, &prepared, iso)?;
        for (w, h) in bench_sizes(args) {
            let target = Target::new(gpu, w, h)?;
            let params = Raymarch::params(&prepared, iso, &camera, w, h);
            let stages = time_frames(gpu, plan, 1, |rec, timer| {
                timer.scope(rec, "raymarch", |rec| {
                    rm.record(rec, &prepared, &target, &params)
                });
            })?;
            let mut r = BenchRecord::new(gpu, "raymarch", "raymarch", "compute", volume.name());
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages);
            r.counts.insert("iso".into(), iso as f64);
            r.counts.insert("occupied_block_fraction".into(), occupied);
            if let Some(ms) = r.median_ms("raymarch") {
                r.counts
                    .insert("mrays_per_s".into(), (w * h) as f64 / ms / 1e3);
            }
            sink.emit(&r)?;
        }
    }
    Ok(())
}

/// The octree build reads the volume once; a buffer copy of the same bytes shows what the
/// memory system allows.
fn minmax_build(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    let compiler = tessera::shaders::compiler();
    for spec in bench_volumes(args) {
        let volume = make_volume(gpu, &spec, args)?;
        let scalar = volume.scalar_type();
        let name = volume.name().to_string();
        let bytes = volume.size_bytes();
        let rm = Raymarch::new(gpu, &compiler, scalar)?;
        let prepared = rm.prepare(gpu, &volume)?;
        let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let src = gpu.upload_buffer("copy source", volume.bytes(), usage)?;
        let dst = gpu.create_buffer("copy destination", bytes, usage, MemoryLocation::GpuOnly)?;
        drop(volume);
        let stages = time_frames(gpu, plan, 2, |rec, timer| {
            timer.scope(rec, "octree-build", |rec| rm.record_build(rec, &prepared));
            rec.barrier();
            timer.scope(rec, "copy", |rec| rec.copy_buffer(&src, &dst, bytes));
        })?;
        let mut r = BenchRecord::new(gpu, "minmax-build", "minmax-octree", "compute", &name);
        (r.warmup, r.frames, r.stages) = (plan.warmup, plan.frames, stages);
        r.counts.insert("volume_bytes".into(), bytes as f64);
        r.counts
            .insert("octree_nodes".into(), prepared.octree.node_count() as f64);
        if let (Some(build), Some(copy)) = (r.median_ms("octree-build"), r.median_ms("copy")) {
            r.counts
                .insert("build_read_gb_per_s".into(), bytes as f64 / build / 1e6);
            r.counts.insert(
                "copy_read_write_gb_per_s".into(),
                2.0 * bytes as f64 / copy / 1e6,
            );
            r.counts.insert("build_over_copy".into(), build / copy);
        }
        sink.emit(&r)?;
    }
    Ok(())
}
