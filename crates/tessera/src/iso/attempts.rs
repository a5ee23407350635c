//! The grow-and-retry loop every GPU extraction shares: extract into buffers of some capacity
//! in a timed submission; if a block's reservation did not fit, grow the buffers to the exact
//! totals the overflowing pass counted and extract again. Nothing is ever silently truncated.

use crate::error::{Error, Result};
use tessera_gpu::{Gpu, Recorder, Timer};

/// Extraction attempts before giving up: the first may overflow, the second is sized by the
/// first's exact totals.
const ATTEMPTS: u32 = 3;

/// One finished extraction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extraction<T> {
    /// What it reserved (the extractor's counters).
    pub totals: T,
    /// GPU time of the attempt that fit, from timestamps around its passes.
    pub gpu_ms: f64,
    /// Attempts made, the last the one that fit.
    pub attempts: u32,
}

/// Records `record` in timed submissions named `name` until `settle` (which reads the
/// counters, and grows the buffers when they overflowed) returns the totals of an attempt
/// that fit.
pub(crate) fn extract_with_retries<T>(
    gpu: &Gpu,
    name: &str,
    mut record: impl FnMut(&Recorder) -> Result<()>,
    mut settle: impl FnMut() -> Result<Option<T>>,
) -> Result<Extraction<T>> {
    let mut timer = Timer::new(gpu, 1)?;
    for attempt in 1..=ATTEMPTS {
        timer.reset(gpu);
        let mut recorded = Ok(());
        gpu.submit(name, |rec| {
            recorded = timer.scope(rec, name, |rec| record(rec));
        })?;
        recorded?;
        if let Some(totals) = settle()? {
            let gpu_ms = timer.read_ms(gpu)?.iter().map(|(_, ms)| ms).sum();
            return Ok(Extraction {
                totals,
                gpu_ms,
                attempts: attempt,
            });
        }
    }
    Err(Error::Invalid(format!(
        "{name} still overflowed its buffers after {ATTEMPTS} attempts"
    )))
}
