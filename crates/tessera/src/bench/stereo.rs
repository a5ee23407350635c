//! The stereo benchmark: a pair of eyes against one, on every isosurface path.

use super::basic::{bench_volumes, make_volume};
use super::iso::techniques;
use super::{time_frames, BenchRecord, FramePlan};
use super::{BenchConfig, RecordSink};
use crate::error::{Error, Result};
use crate::iso::direct::compute::ComputeTarget;
use crate::iso::direct::cull::CullState;
use crate::iso::direct::{Direct, RasterTarget};
use crate::iso::raymarch::Raymarch;
use crate::iso::PreparedVolume;
use crate::target::Target;
use tessera_data::{IsoValue, OrbitCamera};
use tessera_gpu::{Gpu, ShaderCompiler};

/// Two eyes against one: how much a stereo pair costs over a single view (paper D §4.1.3).
/// Ray marching traces both eyes; the mesh path runs twice (with occlusion culling, a state
/// per eye); the compute path extracts once and re-projects for the second eye.
pub fn stereo(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let compiler = crate::shaders::compiler();
    let (w, h) = if config.quick {
        (256, 144)
    } else {
        (3840, 2160)
    };
    let separation = 0.06;
    let camera = OrbitCamera::default();
    let eyes = camera.stereo_pair(separation);
    for spec in bench_volumes(config) {
        let volume = make_volume(gpu, &spec, config)?;
        let iso = volume.iso_to_texel(IsoValue::Normalized(config.iso_fraction));
        let t = techniques(gpu, &compiler, &volume, sink)?;
        let mut multiview_match = None;
        let prepared = t.raymarch.prepare(gpu, &volume)?;
        super::basic::settle(gpu, &t.raymarch, &prepared, iso)?;
        let mut emit = |technique: &str,
                        path: &str,
                        mono: Vec<crate::bench::StageStats>,
                        pair: Vec<crate::bench::StageStats>|
         -> Result<()> {
            let mut r = BenchRecord::new(gpu, "stereo", technique, path, volume.name());
            (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
            let (m, s) = (mono[0].median_ms, pair[0].median_ms);
            r.stages = mono.into_iter().chain(pair).collect();
            r.counts.insert("stereo_over_mono".into(), s / m);
            r.counts.insert("eye_separation".into(), separation as f64);
            sink.emit(&r)
        };

        let targets = [Target::new(gpu, w, h)?, Target::new(gpu, w, h)?];
        let params = eyes.map(|c| Raymarch::params(&prepared, iso, &c, w, h));
        let mono_params = Raymarch::params(&prepared, iso, &camera, w, h);
        let mono = time_frames(gpu, plan, 1, |rec, timer| {
            timer.scope(rec, "mono", |rec| {
                t.raymarch.record(rec, &prepared, &targets[0], &mono_params)
            });
        })?;
        let pair = time_frames(gpu, plan, 1, |rec, timer| {
            timer.scope(rec, "stereo", |rec| {
                t.raymarch.record(rec, &prepared, &targets[0], &params[0]);
                t.raymarch.record(rec, &prepared, &targets[1], &params[1]);
            });
        })?;
        drop(targets);
        emit("raymarch", "compute", mono, pair)?;

        if let Some(direct) = &t.direct {
            let targets = [RasterTarget::new(gpu, w, h)?, RasterTarget::new(gpu, w, h)?];
            let states = [
                CullState::new(gpu, &prepared)?,
                CullState::new(gpu, &prepared)?,
            ];
            let capture = Direct::no_capture(gpu)?;
            let params = eyes.map(|c| Direct::params(&prepared, iso, &c, w, h, 0));
            let mono_params = Direct::params(&prepared, iso, &camera, w, h, 0);
            let mut recorded = Ok(());
            let mono = time_frames(gpu, plan, 1, |rec, timer| {
                let r = timer.scope(rec, "mono", |rec| {
                    direct.record(
                        rec,
                        &prepared,
                        &targets[0],
                        &mono_params,
                        &capture,
                        Some(&states[0]),
                    )
                });
                recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
            });
            let pair = time_frames(gpu, plan, 1, |rec, timer| {
                let r = timer.scope(rec, "stereo", |rec| {
                    (0..2).try_for_each(|e| {
                        direct.record(
                            rec,
                            &prepared,
                            &targets[e],
                            &params[e],
                            &capture,
                            Some(&states[e]),
                        )
                    })
                });
                recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
            });
            // Freed before the multiview run makes its own targets.
            drop((targets, states, capture));
            recorded.map_err(Error::Invalid)?;
            emit("direct+roc", "mesh", mono?, pair?)?;
            if gpu.caps().mesh_multiview {
                multiview_match = Some(multiview(
                    gpu,
                    &compiler,
                    direct,
                    &prepared,
                    iso,
                    (w, h),
                    &eyes,
                    plan,
                    &mut emit,
                )?);
            }
        }

        if let Some(compute) = &t.direct_compute {
            let probe = ComputeTarget::new(gpu, 1, 1, 1)?;
            let probe_pixels = Target::new(gpu, 1, 1)?;
            gpu.submit("count triangles", |rec| {
                compute.record(
                    rec,
                    &prepared,
                    &probe,
                    &probe_pixels,
                    &Direct::params(&prepared, iso, &camera, 1, 1, 1),
                )
            })?;
            drop((probe, probe_pixels));
            let capacity = compute.read_stats(gpu)?.triangles + 1024;
            let targets = [
                ComputeTarget::new(gpu, w, h, capacity)?,
                ComputeTarget::new(gpu, w, h, capacity)?,
            ];
            let pixels = [Target::new(gpu, w, h)?, Target::new(gpu, w, h)?];
            let frame = tessera_data::GridFrame::new(volume.dims(), volume.spacing());
            let right = tessera_data::Projection::new(&eyes[1], &frame, w, h).world_to_clip;
            let params = eyes.map(|c| Direct::params(&prepared, iso, &c, w, h, capacity));
            let mono_params = Direct::params(&prepared, iso, &camera, w, h, capacity);
            let mono = time_frames(gpu, plan, 1, |rec, timer| {
                timer.scope(rec, "mono", |rec| {
                    compute.record(rec, &prepared, &targets[0], &pixels[0], &mono_params)
                });
            })?;
            let pair = time_frames(gpu, plan, 1, |rec, timer| {
                timer.scope(rec, "stereo", |rec| {
                    compute.record(rec, &prepared, &targets[0], &pixels[0], &params[0]);
                    rec.barrier();
                    compute.record_second_view(
                        rec,
                        &targets[0],
                        &targets[1],
                        &pixels[1],
                        &params[1],
                        right,
                    );
                });
            })?;
            emit("direct", "compute", mono, pair)?;
        }
        match multiview_match {
            Some(fraction) => sink.note(&format!(
                "multiview layers match single-eye renders: {fraction:.4} of pixels"
            )),
            None => sink.note(&format!(
                "{} has no multiview mesh shaders",
                gpu.caps().device_name
            )),
        }
    }
    Ok(())
}

type Emit<'a> = dyn FnMut(&str, &str, Vec<crate::bench::StageStats>, Vec<crate::bench::StageStats>) -> Result<()>
    + 'a;

/// Both eyes in one multiview pass against one eye, without culling; also checks that each
/// layer equals a separate render of that eye.
#[allow(clippy::too_many_arguments)]
fn multiview(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    direct: &Direct,
    prepared: &PreparedVolume,
    iso: f32,
    (w, h): (u32, u32),
    eyes: &[OrbitCamera; 2],
    plan: FramePlan,
    emit: &mut Emit,
) -> Result<f64> {
    use crate::iso::direct::stereo::DirectMultiview;
    use crate::iso::direct::FrameOptions;
    let mv = DirectMultiview::new(gpu, compiler, prepared.volume.scalar)?;
    let params = eyes.map(|c| Direct::params(prepared, iso, &c, w, h, 0));
    let views = DirectMultiview::views_buffer(gpu, &params)?;
    let pair_target = RasterTarget::with_views(gpu, w, h, 2)?;
    let mono_target = RasterTarget::new(gpu, w, h)?;
    let capture = Direct::no_capture(gpu)?;
    let mut recorded = Ok(());
    let mono = time_frames(gpu, plan, 1, |rec, timer| {
        let r = timer.scope(rec, "mono", |rec| {
            direct.record(rec, prepared, &mono_target, &params[0], &capture, None)
        });
        recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
    });
    let pair = time_frames(gpu, plan, 1, |rec, timer| {
        let r = timer.scope(rec, "stereo", |rec| {
            mv.record(
                rec,
                direct,
                prepared,
                &pair_target,
                &params[0],
                &views,
                &capture,
            )
        });
        recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
    });
    let layers = pair_target.read_views(gpu);
    let mut matches = 1.0f64;
    if let Ok(layers) = &layers {
        for (e, layer) in layers.iter().enumerate() {
            let single = direct.render(
                gpu,
                prepared,
                &mono_target,
                iso,
                &eyes[e],
                &FrameOptions::default(),
            )?;
            matches = matches.min(layer.compare(&single.image, 2).fraction_within);
        }
    }
    recorded.map_err(Error::Invalid)?;
    layers?;
    emit("direct-multiview", "mesh", mono?, pair?)?;
    Ok(matches)
}
