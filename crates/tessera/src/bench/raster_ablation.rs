//! Where `direct`'s compute frame spends its time (`tessera bench isosurface --ablations`): the
//! frame unculled and culled, its triangles drawn by the raster pass or by the extraction
//! ([`DirectRaster`]), with each of the rasterizer's ways ([`RasterVariant`]): the exact one, a
//! candidate drawing the same frames, and stages left out (unculled only: culling learns from
//! the frames, which then show nothing). Driven below the front door, as the
//! extraction ablations are: an ablated frame is not an image. Records carry the way as their
//! variant ("raster exact", "raster no atomics, in extraction", ...).

use super::basic::bench_sizes;
use super::extraction_ablation::first_extraction_ways;
use super::frames::time_recorded;
use super::{BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::Result;
use crate::iso::direct::compute::{ComputeTarget, DirectCompute, DirectRaster};
use crate::iso::direct::compute_cull::ComputeCullState;
use crate::iso::direct::Direct;
use crate::raster::RasterVariant;
use crate::target::Target;
use tessera_data::{IsoValue, OrbitCamera, Volume};
use tessera_gpu::{Gpu, ShaderCompiler};

/// Culled frames rendered before timing, so that the first pass draws last frame's blocks as
/// in a still view.
pub(super) const CULLED_SETTLING_FRAMES: u32 = 3;

/// What `direct`'s ablations draw: a volume (named `dataset`) at the scenario's isovalue, from
/// the isosurface scenarios' camera.
pub(super) struct AblationScene<'a> {
    pub(super) compiler: ShaderCompiler,
    pub(super) volume: &'a Volume,
    pub(super) dataset: &'a str,
    pub(super) iso: f32,
    pub(super) camera: OrbitCamera,
}

/// Times `direct`'s compute frame with each of the rasterizer's ways, then its first
/// extraction alone each way (`extraction_ablation`), on `volume` at the scenario's sizes.
pub(super) fn direct_ablations(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
    volume: &Volume,
    dataset: &str,
) -> Result<()> {
    if !gpu.caps().buffer_int64_atomics {
        sink.note("no 64-bit buffer atomics: direct's compute path, and its ablations, skipped");
        return Ok(());
    }
    let scene = AblationScene {
        compiler: crate::shaders::compiler(),
        volume,
        dataset,
        iso: volume.iso_to_texel(IsoValue::Normalized(config.iso_fraction)),
        camera: OrbitCamera::default(),
    };
    raster_ways(gpu, config, plan, sink, &scene)?;
    first_extraction_ways(gpu, config, plan, sink, &scene)
}

/// Times every way of the rasterizer in `scene`.
fn raster_ways(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
    scene: &AblationScene,
) -> Result<()> {
    let &AblationScene {
        ref compiler,
        volume,
        dataset,
        iso,
        camera,
    } = scene;
    for raster in [DirectRaster::Pass, DirectRaster::InExtraction] {
        for variant in RasterVariant::ALL {
            if !variant.available(gpu) {
                sink.note(&format!(
                    "the rasterizer's {} is not available on this device: skipped",
                    variant.name()
                ));
                continue;
            }
            let compute =
                DirectCompute::for_measuring(gpu, compiler, volume.scalar_type(), raster, variant)?;
            let prepared = compute.prepare(gpu, volume)?;
            let label = match raster {
                DirectRaster::Pass => format!("raster {}", variant.name()),
                DirectRaster::InExtraction => format!("raster {}, in extraction", variant.name()),
            };
            let capacity = triangles(gpu, &compute, &prepared, iso, &camera)?;
            for (w, h) in bench_sizes(config) {
                let target = ComputeTarget::new(gpu, w, h, capacity)?;
                let pixels = Target::new(gpu, w, h)?;
                let params = Direct::params(&prepared, iso, &camera, w, h, capacity);
                let record = |technique: &str, stages| {
                    let mut r = BenchRecord::new(gpu, "isosurface", technique, "compute", dataset);
                    r.variant = label.clone();
                    (r.width, r.height, r.warmup, r.frames, r.stages) =
                        (w, h, plan.warmup, plan.frames, stages);
                    r.counts.insert("triangles".into(), f64::from(capacity));
                    r
                };
                let stages = time_recorded(gpu, plan, |rec, timer| {
                    timer.scope(rec, "direct", |rec| {
                        compute.record(rec, &prepared, &target, &pixels, &params)
                    });
                    Ok(())
                })?;
                sink.emit(&record("direct", stages))?;
                // Culling learns from the frame: an ablated one shows nothing, so every block
                // would go to the second pass, unlike any real frame.
                if !variant.is_exact() {
                    continue;
                }
                let state = ComputeCullState::new(gpu, &prepared, &target)?;
                for _ in 0..CULLED_SETTLING_FRAMES {
                    compute
                        .render_culled(gpu, &prepared, &target, &pixels, &state, iso, &camera)?;
                }
                let stages = time_recorded(gpu, plan, |rec, timer| {
                    compute.record_culled(
                        rec,
                        &prepared,
                        &target,
                        &pixels,
                        &params,
                        &state,
                        Some(timer),
                    )
                })?;
                sink.emit(&record("direct+hzb", stages))?;
            }
        }
    }
    Ok(())
}

/// The triangles of the surface at `iso`, counted by an extraction into a one-triangle list.
pub(super) fn triangles(
    gpu: &Gpu,
    compute: &DirectCompute,
    prepared: &crate::iso::PreparedVolume,
    iso: f32,
    camera: &OrbitCamera,
) -> Result<u32> {
    let probe = ComputeTarget::new(gpu, 1, 1, 1)?;
    let pixels = Target::new(gpu, 1, 1)?;
    let params = Direct::params(prepared, iso, camera, 1, 1, 1);
    gpu.submit("count triangles", |rec| {
        compute.record(rec, prepared, &probe, &pixels, &params)
    })?;
    Ok(compute.read_stats(gpu)?.triangles.max(1))
}
