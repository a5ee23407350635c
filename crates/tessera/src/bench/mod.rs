//! The benchmark scenarios of the papers, GPU-timed, as records (`tessera bench` prints them
//! and writes them as JSON lines): frame timing, records, and one module per family of
//! scenarios.

mod basic;
mod extraction;
mod extraction_ablation;
mod frames;
mod growth;
mod interval;
mod iso;
mod param;
mod raster_ablation;
pub mod repeat;
mod shell;
mod stereo;

use crate::error::{Error, Result};
use crate::path::Path;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::{SystemTime, UNIX_EPOCH};
use tessera_data::raw::RawOptions;
use tessera_gpu::Gpu;

pub use tessera_gpu::timing::{time_frames, time_once, FramePlan, StageStats};

/// The scenarios, by name.
pub const SCENARIOS: &[&str] = &[
    "pipeline-throughput",
    "raymarch",
    "minmax-build",
    "isosurface",
    "iso-sweep",
    "extraction",
    "time-varying",
    "stereo",
    "interval",
    "shell",
    "param",
    "growth",
];

/// What the scenarios measure beyond their own built-in data.
#[derive(Debug, Clone)]
pub struct BenchConfig {
    pub plan: FramePlan,
    /// Small volumes and images, for CPU drivers and smoke tests.
    pub quick: bool,
    /// Isovalue as a fraction of the value range for the isosurface scenarios.
    pub iso_fraction: f32,
    /// A volume for the isosurface scenarios instead of the head phantoms, or a tet mesh for
    /// `interval` besides the procedural meshes (a file or a spec).
    pub data: Option<String>,
    /// How to read `data` when it is a raw volume.
    pub raw: RawOptions,
    /// Paths `interval`, `extraction`, `isosurface` and `iso-sweep` measure (empty: every path
    /// the device has; `extraction`'s graphics path is the task/mesh extraction; the
    /// isosurface scenarios' ray marching runs on any).
    pub paths: Vec<Path>,
    /// Image sizes to measure, in this order (empty: each scenario's own).
    pub sizes: Vec<(u32, u32)>,
    /// `extraction` also times each extractor with stages left out
    /// ([`crate::iso::ablation::Ablation`]), `isosurface` `direct`'s compute frame with each of
    /// the rasterizer's ways ([`crate::raster::RasterVariant`]), for performance work.
    pub ablations: bool,
    /// `interval` times only the variants whose label holds this text (all when `None`);
    /// `isosurface` and `iso-sweep` take "hidden-side" or "raster-in-extraction".
    pub variants: Option<String>,
    /// `isosurface` and `iso-sweep` time only the techniques of these record names (e.g.
    /// "direct+hzb"), and ray marching, the reference of their speed-ups (empty: every one).
    pub techniques: Vec<String>,
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            plan: FramePlan::default(),
            quick: false,
            iso_fraction: 0.3,
            data: None,
            raw: RawOptions::default(),
            paths: Vec::new(),
            sizes: Vec::new(),
            ablations: false,
            variants: None,
            techniques: Vec::new(),
        }
    }
}

/// Where the records go as they are measured.
pub trait RecordSink {
    fn emit(&mut self, record: &BenchRecord) -> Result<()>;
    /// A remark about the device or a result that is not a record (a skipped path, a ratio).
    fn note(&mut self, text: &str);
}

/// Refuses options that none of `scenarios` reads, before any of them runs.
pub fn check_options(scenarios: &[&str], config: &BenchConfig) -> Result<()> {
    let refuse = |option: &str, readers: &[&str]| -> Result<()> {
        if scenarios.iter().any(|s| readers.contains(s)) {
            return Ok(());
        }
        Err(Error::Invalid(format!(
            "{option} is read by {}; {} reads none",
            readers.join(", "),
            scenarios.join(", ")
        )))
    };
    if config.variants.is_some() {
        refuse(
            "variants (--variants)",
            &["interval", "isosurface", "iso-sweep"],
        )?;
    }
    if !config.techniques.is_empty() {
        refuse("techniques (--techniques)", &["isosurface", "iso-sweep"])?;
    }
    Ok(())
}

/// Runs the scenario `name` (one of [`SCENARIOS`]).
pub fn run(gpu: &Gpu, name: &str, config: &BenchConfig, sink: &mut dyn RecordSink) -> Result<()> {
    let keep_busy_ms = config.plan.keep_busy_ms;
    if !(keep_busy_ms.is_finite() && keep_busy_ms >= 0.0) {
        return Err(Error::Invalid(format!(
            "keep_busy_ms (--keep-busy-ms) is milliseconds, 0 or more, not {keep_busy_ms}"
        )));
    }
    // Quick runs are smoke tests on CPU drivers, whose frame times need not settle and whose
    // clocks need no keeping up: exactly the warm-up asked for, nothing between frames.
    let plan = if config.quick {
        FramePlan {
            max_warmup: 0,
            keep_busy_ms: 0.0,
            ..config.plan
        }
    } else {
        config.plan
    };
    let sink = &mut Stamped {
        sink,
        keep_busy_ms: plan.keep_busy_ms,
    };
    match name {
        "pipeline-throughput" => basic::throughput(gpu, config, plan, sink),
        "raymarch" => basic::raymarch(gpu, config, plan, sink),
        "minmax-build" => basic::minmax_build(gpu, config, plan, sink),
        "isosurface" => iso::isosurface(gpu, config, plan, sink),
        "iso-sweep" => iso::iso_sweep(gpu, config, plan, sink),
        "extraction" => extraction::extraction(gpu, config, plan, sink),
        "time-varying" => iso::time_varying(gpu, config, plan, sink),
        "stereo" => stereo::stereo(gpu, config, plan, sink),
        "interval" => interval::interval(gpu, config, plan, sink),
        "shell" => shell::shell(gpu, config, plan, sink),
        "param" => param::param(gpu, config, plan, sink),
        "growth" => growth::growth(gpu, config, plan, sink),
        _ => Err(Error::Invalid(format!(
            "unknown scenario '{name}'; choose one of {} or all",
            SCENARIOS.join(", ")
        ))),
    }
}

/// Passes records on with what the plan ran them under, which no scenario sets itself.
struct Stamped<'a> {
    sink: &'a mut dyn RecordSink,
    keep_busy_ms: f64,
}

impl RecordSink for Stamped<'_> {
    fn emit(&mut self, record: &BenchRecord) -> Result<()> {
        self.sink.emit(&BenchRecord {
            keep_busy_ms: self.keep_busy_ms,
            ..record.clone()
        })
    }

    fn note(&mut self, text: &str) {
        self.sink.note(text);
    }
}

/// One line of `tessera bench` output.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRecord {
    pub scenario: String,
    pub technique: String,
    /// Which pipeline ran it: "compute", "fragment", "mesh", …
    pub path: String,
    /// Settings that distinguish runs of one technique and path (empty when there are none).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub variant: String,
    pub dataset: String,
    pub width: u32,
    pub height: u32,
    /// Warm-up frames at least (each stage says how many its measurement ran).
    pub warmup: u32,
    pub frames: u32,
    /// Which run of the scenario measured it (`tessera bench --repeat`), from 0.
    pub repeat: u32,
    pub stages: Vec<StageStats>,
    pub counts: BTreeMap<String, f64>,
    pub device: String,
    pub driver: String,
    /// When the record was made (seconds since 1970-01-01 UTC), to line records up with logs
    /// kept beside a run, such as the GPU's clocks that `scripts/gpu-bench.sh` writes.
    pub unix_time_s: f64,
    /// GPU milliseconds each timed frame plus the arithmetic dispatch after it took
    /// ([`FramePlan::keep_busy_ms`]; 0: frames with idle gaps between them).
    pub keep_busy_ms: f64,
}

impl BenchRecord {
    pub fn new(
        gpu: &Gpu,
        scenario: &str,
        technique: &str,
        path: &str,
        dataset: &str,
    ) -> BenchRecord {
        let caps = gpu.caps();
        BenchRecord {
            scenario: scenario.into(),
            technique: technique.into(),
            path: path.into(),
            variant: String::new(),
            dataset: dataset.into(),
            width: 0,
            height: 0,
            warmup: 0,
            frames: 0,
            repeat: 0,
            stages: vec![],
            counts: BTreeMap::new(),
            device: caps.device_name.clone(),
            driver: format!("{} {}", caps.driver_name, caps.driver_info),
            unix_time_s: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0.0, |t| t.as_secs_f64()),
            keep_busy_ms: 0.0,
        }
    }

    /// The median time of a whole frame: its span where it has several stages (their sum
    /// where no span was recorded), else its one stage. Speed-ups and frame rates come from
    /// it, so that a frame timed pass by pass counts what runs between its passes as a frame
    /// timed in one piece does.
    pub fn frame_ms(&self) -> Option<f64> {
        match self.stages.as_slice() {
            [one] => Some(one.median_ms),
            _ => self
                .median_ms(frames::FRAME_SPAN_STAGE)
                .or_else(|| self.median_ms(frames::FRAME_STAGE)),
        }
    }

    /// Adds what the renderer counted in its last frame: triangles, blocks drawn and its own
    /// details (e.g. interval shading's scheme: tets binned, tiled, overflowed).
    pub fn add_frame_stats(&mut self, stats: &crate::renderer::FrameStats) {
        if let Some(t) = stats.triangles {
            self.counts.insert("triangles_last_frame".into(), t as f64);
        }
        if let Some((first, new)) = stats.blocks_drawn {
            self.counts
                .insert("blocks_drawn".into(), (first + new) as f64);
            self.counts
                .insert("blocks_drawn_first".into(), first as f64);
            self.counts.insert("blocks_drawn_new".into(), new as f64);
        }
        for (name, &n) in &stats.details {
            self.counts.insert((*name).into(), n as f64);
        }
    }

    pub fn median_ms(&self, stage: &str) -> Option<f64> {
        self.stages
            .iter()
            .find(|s| s.stage == stage)
            .map(|s| s.median_ms)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(stages: &[(&str, f64)]) -> BenchRecord {
        BenchRecord {
            scenario: "isosurface".into(),
            technique: "direct+hzb".into(),
            path: "compute".into(),
            variant: String::new(),
            dataset: "head".into(),
            width: 64,
            height: 48,
            warmup: 0,
            frames: 1,
            repeat: 0,
            stages: stages
                .iter()
                .map(|&(name, ms)| StageStats::from_samples(name, &[ms]))
                .collect(),
            counts: BTreeMap::new(),
            device: String::new(),
            driver: String::new(),
            unix_time_s: 0.0,
            keep_busy_ms: 0.0,
        }
    }

    #[test]
    fn a_whole_frame_is_its_span_else_its_sum_else_its_one_stage() {
        let passes = [("a", 1.0), ("b", 2.0), ("frame", 3.0)];
        assert_eq!(record(&passes).frame_ms(), Some(3.0));
        let spanned = [passes.as_slice(), &[("frame-span", 3.5)]].concat();
        assert_eq!(record(&spanned).frame_ms(), Some(3.5));
        assert_eq!(record(&[("raymarch", 1.25)]).frame_ms(), Some(1.25));
        assert_eq!(record(&[("a", 1.0), ("b", 2.0)]).frame_ms(), None);
    }
}
