//! The benchmark scenarios of the papers, GPU-timed, as records (`tessera bench` prints them
//! and writes them as JSON lines): frame timing, records, and one module per family of
//! scenarios.

mod basic;
mod hzb;
mod interval;
mod iso;
mod param;
mod stereo;

use crate::error::{Error, Result};
use crate::path::Path;
use serde::Serialize;
use std::collections::BTreeMap;
use tessera_data::raw::RawOptions;
use tessera_gpu::{Gpu, Recorder, Timer};

/// The scenarios, by name.
pub const SCENARIOS: &[&str] = &[
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
    /// Paths `interval` measures (empty: every path the device has).
    pub paths: Vec<Path>,
    /// Image sizes to measure, in this order (empty: each scenario's own).
    pub sizes: Vec<(u32, u32)>,
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            plan: FramePlan {
                warmup: 10,
                frames: 100,
            },
            quick: false,
            iso_fraction: 0.3,
            data: None,
            raw: RawOptions::default(),
            paths: Vec::new(),
            sizes: Vec::new(),
        }
    }
}

/// Where the records go as they are measured.
pub trait RecordSink {
    fn emit(&mut self, record: &BenchRecord) -> Result<()>;
    /// A remark about the device or a result that is not a record (a skipped path, a ratio).
    fn note(&mut self, text: &str);
}

/// Runs the scenario `name` (one of [`SCENARIOS`]).
pub fn run(gpu: &Gpu, name: &str, config: &BenchConfig, sink: &mut dyn RecordSink) -> Result<()> {
    let plan = config.plan;
    match name {
        "pipeline-throughput" => basic::throughput(gpu, config, plan, sink),
        "raymarch" => basic::raymarch(gpu, config, plan, sink),
        "minmax-build" => basic::minmax_build(gpu, config, plan, sink),
        "isosurface" => iso::isosurface(gpu, config, plan, sink),
        "iso-sweep" => iso::iso_sweep(gpu, config, plan, sink),
        "time-varying" => iso::time_varying(gpu, config, plan, sink),
        "stereo" => stereo::stereo(gpu, config, plan, sink),
        "interval" => interval::interval(gpu, config, plan, sink),
        "param" => param::param(gpu, config, plan, sink),
        _ => Err(Error::Invalid(format!(
            "unknown scenario '{name}'; choose one of {} or all",
            SCENARIOS.join(", ")
        ))),
    }
}

/// Frame counts for one measurement.
#[derive(Debug, Clone, Copy)]
pub struct FramePlan {
    pub warmup: u32,
    pub frames: u32,
}

impl Default for FramePlan {
    fn default() -> Self {
        FramePlan {
            warmup: 10,
            frames: 100,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct StageStats {
    pub stage: String,
    pub median_ms: f64,
    pub min_ms: f64,
    pub max_ms: f64,
}

impl StageStats {
    pub fn from_samples(stage: &str, samples: &[f64]) -> StageStats {
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        let median = match s.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => s[n / 2],
            n => 0.5 * (s[n / 2 - 1] + s[n / 2]),
        };
        StageStats {
            stage: stage.to_string(),
            median_ms: median,
            min_ms: s.first().copied().unwrap_or(f64::NAN),
            max_ms: s.last().copied().unwrap_or(f64::NAN),
        }
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
    pub warmup: u32,
    pub frames: u32,
    pub stages: Vec<StageStats>,
    pub counts: BTreeMap<String, f64>,
    pub device: String,
    pub driver: String,
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
            stages: vec![],
            counts: BTreeMap::new(),
            device: caps.device_name.clone(),
            driver: format!("{} {}", caps.driver_name, caps.driver_info),
        }
    }

    pub fn median_ms(&self, stage: &str) -> Option<f64> {
        self.stages
            .iter()
            .find(|s| s.stage == stage)
            .map(|s| s.median_ms)
    }
}

/// Submits `plan.warmup + plan.frames` frames recorded by `record` (which opens timer scopes)
/// and returns per-stage statistics over the timed frames.
pub fn time_frames(
    gpu: &Gpu,
    plan: FramePlan,
    max_scopes: u32,
    mut record: impl FnMut(&Recorder, &mut Timer),
) -> Result<Vec<StageStats>> {
    let mut timer = Timer::new(gpu, max_scopes)?;
    let mut samples: Vec<(String, Vec<f64>)> = Vec::new();
    for frame in 0..plan.warmup + plan.frames {
        timer.reset(gpu);
        gpu.submit("benchmark frame", |rec| record(rec, &mut timer))?;
        if frame < plan.warmup {
            continue;
        }
        for (i, (name, ms)) in timer.read_ms(gpu)?.into_iter().enumerate() {
            if samples.len() <= i {
                samples.push((name, Vec::new()));
            }
            samples[i].1.push(ms);
        }
    }
    Ok(samples
        .iter()
        .map(|(name, s)| StageStats::from_samples(name, s))
        .collect())
}

/// Submits one frame that `record` records, timed as a whole; returns its GPU milliseconds.
/// For single renders (tests, `tessera render`); benchmarks use [`time_frames`].
pub fn time_once(
    gpu: &Gpu,
    pass: &str,
    record: impl FnOnce(&Recorder) -> Result<()>,
) -> Result<f64> {
    let mut timer = Timer::new(gpu, 1)?;
    timer.reset(gpu);
    let mut recorded = Ok(());
    let submitted = gpu.submit(pass, |rec| {
        recorded = timer.scope(rec, pass, record);
    });
    submitted
        .map_err(crate::Error::from)
        .and(recorded)
        .and_then(|_| Ok(timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0)))
}

/// The `u32` words of a small GPU buffer (counters, statistics).
pub fn read_words(gpu: &Gpu, buffer: &tessera_gpu::Buffer) -> Result<Vec<u32>> {
    Ok(bytemuck::allocation::pod_collect_to_vec(
        &gpu.read_buffer(buffer)?,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_median_min_max() {
        let s = StageStats::from_samples("x", &[3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.median_ms, s.min_ms, s.max_ms), (2.5, 1.0, 10.0));
        let s = StageStats::from_samples("x", &[5.0, 1.0, 2.0]);
        assert_eq!(s.median_ms, 2.0);
    }
}
