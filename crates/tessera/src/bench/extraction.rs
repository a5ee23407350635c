//! Paper C's extraction comparison: on the same volume and isovalue, GPU time of one
//! extraction and the bytes of the stored surface, for the meshlet extraction (each path the
//! device has) and Parallel Marching Blocks at every block size. Buffers are sized by a first
//! extraction, so the timed ones never overflow.

use super::basic::{bench_volumes, make_volume};
use super::{time_frames, BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::Result;
use crate::iso::ablation::Ablation;
use crate::iso::meshlets::{ExtractionPath, MeshletExtractor};
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::pmb::{PmbExtractor, PmbInvocations, PmbTuning};
use crate::iso::PreparedVolume;
use crate::path::Path;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::pmb::PmbBlockSize;
use tessera_data::IsoValue;
use tessera_gpu::Gpu;

pub(super) fn extraction(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let compiler = crate::shaders::compiler();
    let rule = AmbiguityRule::default();
    let caps = gpu.caps();
    let wanted = |p: Path| config.paths.is_empty() || config.paths.contains(&p);
    let mut paths = Vec::new();
    if wanted(Path::Compute) {
        paths.push((ExtractionPath::Compute, "compute"));
    }
    if caps.mesh_shader && caps.task_shader && wanted(Path::Graphics) {
        paths.push((ExtractionPath::MeshShaders, "mesh"));
    }
    for spec in bench_volumes(config) {
        let volume = make_volume(gpu, &spec, config)?;
        let (scalar, name) = (volume.scalar_type(), volume.name().to_string());
        let iso = volume.iso_to_texel(IsoValue::Normalized(config.iso_fraction));
        let builder = MinMaxBuilder::new(gpu, &compiler, scalar)?;
        let prepared = PreparedVolume::new(gpu, &builder, &volume)?;
        drop(volume);
        let mut best_pmb: Option<(f64, u64)> = None;
        // The fastest PMB in the layout paper C measured against (one invocation per sample).
        let mut best_per_sample_pmb = f64::INFINITY;
        for size in PmbBlockSize::ALL {
            let pmb = PmbExtractor::new(gpu, &compiler, scalar, rule, size)?;
            let mut out = pmb.buffers(gpu, &prepared, Default::default())?;
            let first = pmb.extract_into(gpu, &prepared, iso, &mut out)?;
            // Every variant below writes into the buffers this whole extraction grew.
            let time = |ex: &PmbExtractor| {
                time_frames(gpu, plan, 1, |rec, timer| {
                    timer.scope(rec, "extraction", |rec| {
                        ex.record(rec, &prepared, iso, &out)
                    });
                })
            };
            let stages = time(&pmb)?;
            let mut r = BenchRecord::new(gpu, "extraction", "pmb", "compute", &name);
            r.variant = size.name();
            (r.warmup, r.frames, r.stages) = (plan.warmup, plan.frames, stages);
            let bytes = first.totals.stored_bytes();
            r.counts.insert("stored_bytes".into(), bytes as f64);
            r.counts
                .insert("triangles".into(), f64::from(first.totals.triangles));
            r.counts
                .insert("vertices".into(), f64::from(first.totals.vertices));
            if let Some(ms) = r.median_ms("extraction") {
                let (best_ms, best_bytes) = best_pmb.unwrap_or((f64::INFINITY, u64::MAX));
                best_pmb = Some((best_ms.min(ms), best_bytes.min(bytes)));
            }
            sink.emit(&r)?;
            for &ablation in if config.ablations {
                &Ablation::PMB[..]
            } else {
                &[]
            } {
                let tuning = PmbTuning {
                    ablation,
                    ..PmbTuning::default()
                };
                let ablated = PmbExtractor::tuned(gpu, &compiler, scalar, rule, size, tuning)?;
                let stages = time(&ablated)?;
                let cell = Cell {
                    technique: "pmb",
                    path: "compute",
                    dataset: &name,
                };
                sink.emit(&cell.ablated(gpu, &size.name(), ablation, plan, stages))?;
            }
            // The layout of Liu et al.'s pseudocode, which paper C measured against.
            let tuning = PmbTuning {
                invocations: PmbInvocations::OnePerSample,
                ..PmbTuning::default()
            };
            match PmbExtractor::tuned(gpu, &compiler, scalar, rule, size, tuning) {
                Ok(per_sample) => {
                    let stages = time(&per_sample)?;
                    let mut r = BenchRecord::new(gpu, "extraction", "pmb", "compute", &name);
                    r.variant = format!("{}, {}", size.name(), tuning.invocations.name());
                    (r.warmup, r.frames, r.stages) = (plan.warmup, plan.frames, stages);
                    if let Some(ms) = r.median_ms("extraction") {
                        best_per_sample_pmb = best_per_sample_pmb.min(ms);
                    }
                    sink.emit(&r)?;
                }
                Err(e) => sink.note(&format!("PMB {}: {e}", size.name())),
            }
        }
        for &(path, path_name) in &paths {
            let ex = MeshletExtractor::new(gpu, &compiler, scalar, rule, path)?;
            let mut out = ex.buffers(gpu, &prepared, Default::default())?;
            let first = ex.extract_into(gpu, &prepared, iso, &mut out)?;
            // The ablated extractions write into the buffers the whole one grew.
            let time = |ex: &MeshletExtractor| {
                let mut recorded = Ok(());
                let stages = time_frames(gpu, plan, 1, |rec, timer| {
                    let result = timer.scope(rec, "extraction", |rec| {
                        ex.record(rec, &prepared, iso, &out)
                    });
                    recorded = recorded.clone().and(result.map_err(|e| e.to_string()));
                })?;
                recorded.map_err(crate::error::Error::Invalid)?;
                Ok::<_, crate::error::Error>(stages)
            };
            let stages = time(&ex)?;
            let mut r = BenchRecord::new(gpu, "extraction", "meshlets", path_name, &name);
            (r.warmup, r.frames, r.stages) = (plan.warmup, plan.frames, stages);
            let bytes = first.totals.stored_bytes();
            r.counts.insert("stored_bytes".into(), bytes as f64);
            r.counts
                .insert("meshlets".into(), f64::from(first.totals.meshlets));
            r.counts
                .insert("vertices".into(), f64::from(first.totals.vertices));
            if let Some(ms) = r
                .median_ms("extraction")
                .filter(|_| best_per_sample_pmb.is_finite())
            {
                r.counts.insert(
                    "speedup_over_best_per_sample_pmb".into(),
                    best_per_sample_pmb / ms,
                );
            }
            if let (Some(ms), Some((best_ms, best_bytes))) = (r.median_ms("extraction"), best_pmb) {
                r.counts
                    .insert("speedup_over_best_pmb".into(), best_ms / ms);
                r.counts.insert(
                    "bytes_over_smallest_pmb".into(),
                    bytes as f64 / best_bytes as f64,
                );
            }
            sink.emit(&r)?;
            for &ablation in if config.ablations {
                &Ablation::MESHLETS[..]
            } else {
                &[]
            } {
                let ablated =
                    MeshletExtractor::ablated(gpu, &compiler, scalar, rule, path, ablation)?;
                let stages = time(&ablated)?;
                let cell = Cell {
                    technique: "meshlets",
                    path: path_name,
                    dataset: &name,
                };
                sink.emit(&cell.ablated(gpu, "", ablation, plan, stages))?;
            }
        }
    }
    Ok(())
}

/// Which extraction an ablated record belongs to.
struct Cell<'a> {
    technique: &'a str,
    path: &'a str,
    dataset: &'a str,
}

impl Cell<'_> {
    /// The record of `stages` timed with `ablation`; its variant names the ablation after
    /// `variant` (PMB's block size).
    fn ablated(
        &self,
        gpu: &Gpu,
        variant: &str,
        ablation: Ablation,
        plan: FramePlan,
        stages: Vec<super::StageStats>,
    ) -> BenchRecord {
        let mut r = BenchRecord::new(gpu, "extraction", self.technique, self.path, self.dataset);
        r.variant = if variant.is_empty() {
            format!("ablation: {}", ablation.name())
        } else {
            format!("{variant}, ablation: {}", ablation.name())
        };
        (r.warmup, r.frames, r.stages) = (plan.warmup, plan.frames, stages);
        r
    }
}
