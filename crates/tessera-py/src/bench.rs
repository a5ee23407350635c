//! `bench`: the library's benchmark scenarios (as `tessera bench` runs them), their records
//! handed to Python as JSON lines for the pure-Python wrapper to parse into dicts.

use pyo3::prelude::*;
use tessera::bench::{self, BenchConfig, BenchRecord, FramePlan, RecordSink};
use tessera::path::Path;

use crate::device::Device;
use crate::errors::{from_tessera, guarded, DataError};

/// Keeps every record as a JSON line, and the notes.
#[derive(Default)]
struct Collected {
    records: Vec<String>,
    notes: Vec<String>,
}

impl RecordSink for Collected {
    fn emit(&mut self, record: &BenchRecord) -> tessera::Result<()> {
        let line = serde_json::to_string(record)
            .map_err(|e| tessera::Error::Invalid(format!("a benchmark record: {e}")))?;
        self.records.push(line);
        Ok(())
    }

    fn note(&mut self, text: &str) {
        self.notes.push(text.to_string());
    }
}

/// Runs benchmark `scenario` (one of `tessera bench`'s) on `device`; returns its records as
/// JSON lines and its notes. GPU timestamps, medians of `frames` after `warmup`; each frame
/// followed by an arithmetic-only dispatch up to `keep_busy_ms` of GPU time (the library's
/// default when `None`; 0 leaves the GPU idle between frames); `techniques`: the isosurface
/// scenarios' techniques to time besides ray marching (all when `None`); `paths`, `variants`
/// and `ablations` as `tessera bench`'s flags of those names.
#[pyfunction]
#[pyo3(signature = (device, scenario, quick=false, frames=100, warmup=10, iso_fraction=0.3, data=None, sizes=None, keep_busy_ms=None, techniques=None, paths=None, variants=None, ablations=false))]
#[allow(clippy::too_many_arguments)]
fn _bench(
    py: Python<'_>,
    device: &Device,
    scenario: &str,
    quick: bool,
    frames: u32,
    warmup: u32,
    iso_fraction: f32,
    data: Option<String>,
    sizes: Option<Vec<(u32, u32)>>,
    keep_busy_ms: Option<f64>,
    techniques: Option<Vec<String>>,
    paths: Option<Vec<String>>,
    variants: Option<String>,
    ablations: bool,
) -> PyResult<(Vec<String>, Vec<String>)> {
    if !bench::SCENARIOS.contains(&scenario) {
        return Err(DataError::new_err(format!(
            "unknown scenario '{scenario}'; choose one of {}",
            bench::SCENARIOS.join(", ")
        )));
    }
    if frames == 0 {
        return Err(DataError::new_err("frames must be at least 1"));
    }
    if !(0.0..=1.0).contains(&iso_fraction) {
        return Err(DataError::new_err(format!(
            "iso_fraction {iso_fraction}: a fraction of the value range, 0 to 1"
        )));
    }
    let keep_busy_ms = keep_busy_ms.unwrap_or(FramePlan::default().keep_busy_ms);
    let paths = paths
        .unwrap_or_default()
        .iter()
        .map(|p| Path::parse(p))
        .collect::<tessera::Result<Vec<Path>>>()
        .map_err(from_tessera)?;
    let config = BenchConfig {
        plan: FramePlan {
            warmup,
            frames,
            keep_busy_ms,
            ..FramePlan::default()
        },
        quick,
        iso_fraction,
        data,
        sizes: sizes.unwrap_or_default(),
        techniques: techniques.unwrap_or_default(),
        paths,
        variants,
        ablations,
        ..BenchConfig::default()
    };
    bench::check_options(&[scenario], &config).map_err(from_tessera)?;
    let gpu = device.gpu.clone();
    py.detach(|| {
        guarded("benchmarking", || {
            let gpu = Device::lock(&gpu);
            let mut sink = Collected::default();
            bench::run(&gpu, scenario, &config, &mut sink).map_err(from_tessera)?;
            Ok((sink.records, sink.notes))
        })
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(_bench, m)?)?;
    Ok(())
}
