//! Where `direct`'s extraction of a block list spends its time (`tessera bench isosurface
//! --ablations`): pass A's extraction of a still, culled view timed alone, whole, with stages
//! left out (no vertex arithmetic, no triangle written, samples only) and with each corner
//! made by its own invocation ([`FirstExtractionWay`]), over the blocks the settled frames
//! saw. Records carry the way as their variant ("pass A extraction, samples only", ...), the
//! blocks and triangles as counts.

use super::basic::bench_sizes;
use super::frames::time_recorded;
use super::raster_ablation::{triangles, AblationScene, CULLED_SETTLING_FRAMES};
use super::{BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::Result;
use crate::iso::direct::compute::{ComputeTarget, DirectCompute};
use crate::iso::direct::compute_cull::{
    measured_list_extraction, ComputeCullState, FirstExtractionWay,
};
use crate::iso::direct::Direct;
use crate::target::Target;
use tessera_gpu::Gpu;

/// The timer scope of the extraction.
const STAGE: &str = "pass-a-extraction";

/// Times pass A's extraction each way in `scene`, at the scenario's sizes.
pub(super) fn first_extraction_ways(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
    scene: &AblationScene,
) -> Result<()> {
    let (volume, iso, camera) = (scene.volume, scene.iso, scene.camera);
    let compiler = &scene.compiler;
    let compute = DirectCompute::new(gpu, compiler, volume.scalar_type())?;
    let prepared = compute.prepare(gpu, volume)?;
    let capacity = triangles(gpu, &compute, &prepared, iso, &camera)?;
    let ways = FirstExtractionWay::all()
        .into_iter()
        .map(|way| {
            let pipeline = measured_list_extraction(gpu, compiler, volume.scalar_type(), way)?;
            Ok((way, pipeline))
        })
        .collect::<Result<Vec<_>>>()?;
    for (w, h) in bench_sizes(config) {
        let target = ComputeTarget::new(gpu, w, h, capacity)?;
        let pixels = Target::new(gpu, w, h)?;
        let state = ComputeCullState::new(gpu, &prepared, &target)?;
        let mut settled = None;
        for _ in 0..CULLED_SETTLING_FRAMES {
            let (_, _, stats) =
                compute.render_culled(gpu, &prepared, &target, &pixels, &state, iso, &camera)?;
            settled = Some(stats);
        }
        let params = Direct::params(&prepared, iso, &camera, w, h, capacity);
        for (way, pipeline) in &ways {
            let stages = time_recorded(gpu, plan, |rec, timer| {
                compute.record_first_extraction(
                    rec,
                    (timer, STAGE),
                    pipeline,
                    &prepared,
                    &target,
                    &params,
                    &state,
                )
            })?;
            let mut r = BenchRecord::new(gpu, "isosurface", "direct+hzb", "compute", scene.dataset);
            r.variant = format!("pass A extraction, {}", way.name());
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages);
            if let Some(stats) = settled {
                r.counts
                    .insert("blocks".into(), f64::from(stats.blocks_drawn_first));
                r.counts
                    .insert("triangles".into(), f64::from(stats.triangles_first));
            }
            sink.emit(&r)?;
        }
    }
    Ok(())
}
