//! The compute path of `direct` with HZB occlusion culling (`direct+hzb`) in the isosurface
//! benchmarks: its culling state carries over from frame to frame, and its four stages are
//! timed apart.

use super::{BenchRecord, FramePlan, StageStats};
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, DirectCompute};
use crate::iso::direct::compute_cull::ComputeCullState;
use crate::iso::direct::Direct;
use crate::iso::PreparedVolume;
use crate::target::Target;
use tessera_data::OrbitCamera;
use tessera_gpu::{Gpu, Recorder, Timer};

/// Times the compute path with HZB occlusion culling (`direct+hzb`) into `r` (frame size and
/// plan already set), its culling state carried from frame to frame.
pub(super) fn measure_compute_culled(
    gpu: &Gpu,
    compute: &DirectCompute,
    prepared: &PreparedVolume,
    capacity: u32,
    plan: FramePlan,
    iso_of: &dyn Fn(u32) -> f32,
    r: &mut BenchRecord,
) -> Result<()> {
    let camera = OrbitCamera::default();
    let (w, h) = (r.width, r.height);
    let target = ComputeTarget::new(gpu, w, h, capacity)?;
    let pixels = Target::new(gpu, w, h)?;
    let state = ComputeCullState::new(gpu, prepared, &target)?;
    let stages = time_culled_frames(gpu, plan, |frame, rec, timer| {
        let params = Direct::params(prepared, iso_of(frame), &camera, w, h, capacity);
        compute.record_culled(
            rec,
            prepared,
            &target,
            &pixels,
            &params,
            &state,
            Some(timer),
        )
    });
    let (stages, stats) = (stages?, state.read_stats(gpu)?);
    if stats.triangles_first.max(stats.triangles_new) > capacity {
        return Err(Error::Invalid(format!(
            "direct+hzb: a pass made {} triangles, the lists hold {capacity}",
            stats.triangles_first.max(stats.triangles_new)
        )));
    }
    r.stages = stages;
    let counts = [
        ("triangles_last_frame", stats.triangles()),
        ("triangles_first_pass", stats.triangles_first),
        ("triangles_second_pass", stats.triangles_new),
        ("blocks_occupied", stats.blocks_occupied),
        ("blocks_visible", stats.blocks_visible),
        ("blocks_drawn", stats.blocks_drawn()),
        ("blocks_drawn_first", stats.blocks_drawn_first),
        ("blocks_drawn_new", stats.blocks_drawn_new),
    ];
    for (name, n) in counts {
        r.counts.insert(name.into(), n as f64);
    }
    Ok(())
}

/// Like `crate::bench::time_frames` for culled frames, whose four stages are timed apart: their
/// statistics, then those of "direct", each frame's stages summed (they follow each other).
fn time_culled_frames(
    gpu: &Gpu,
    plan: FramePlan,
    mut record: impl FnMut(u32, &Recorder, &mut Timer) -> crate::Result<()>,
) -> Result<Vec<StageStats>> {
    let mut timer = Timer::new(gpu, 4)?;
    let mut samples: Vec<(String, Vec<f64>)> = Vec::new();
    let mut totals = Vec::new();
    for frame in 0..plan.warmup + plan.frames {
        timer.reset(gpu);
        let mut recorded = Ok(());
        gpu.submit("benchmark frame", |rec| {
            recorded = record(frame, rec, &mut timer)
        })?;
        recorded?;
        if frame < plan.warmup {
            continue;
        }
        let stages = timer.read_ms(gpu)?;
        totals.push(stages.iter().map(|s| s.1).sum::<f64>());
        for (i, (name, ms)) in stages.into_iter().enumerate() {
            if samples.len() <= i {
                samples.push((name, Vec::new()));
            }
            samples[i].1.push(ms);
        }
    }
    let mut stages: Vec<_> = samples
        .iter()
        .map(|(name, s)| StageStats::from_samples(name, s))
        .collect();
    stages.push(StageStats::from_samples("direct", &totals));
    Ok(stages)
}
