//! GPU timing of whole frames: many frames per stage with statistics (benchmarks), or one
//! frame timed as a whole (single renders), and reading small counter buffers.

use crate::commands::Recorder;
use crate::context::Gpu;
use crate::error::{GpuError, Result};
use crate::memory::Buffer;
use crate::timer::Timer;
use serde::Serialize;

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
pub fn time_once<E: From<GpuError>>(
    gpu: &Gpu,
    pass: &str,
    record: impl FnOnce(&Recorder) -> std::result::Result<(), E>,
) -> std::result::Result<f64, E> {
    let mut timer = Timer::new(gpu, 1).map_err(E::from)?;
    timer.reset(gpu);
    let mut recorded = Ok(());
    let submitted = gpu.submit(pass, |rec| {
        recorded = timer.scope(rec, pass, record);
    });
    submitted.map_err(E::from).and(recorded).and_then(|_| {
        Ok(timer
            .read_ms(gpu)
            .map_err(E::from)?
            .first()
            .map(|s| s.1)
            .unwrap_or(0.0))
    })
}

/// The `u32` words of a small GPU buffer (counters, statistics).
pub fn read_words(gpu: &Gpu, buffer: &Buffer) -> Result<Vec<u32>> {
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
