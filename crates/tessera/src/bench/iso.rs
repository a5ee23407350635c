//! Isosurface benchmark scenarios that set techniques side by side in one run.

use super::basic::{bench_sizes, bench_volumes, make_volume};
use super::{time_frames, BenchRecord, FramePlan};
use super::{BenchConfig, RecordSink};
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, DirectCompute};
use crate::iso::direct::cull::CullState;
use crate::iso::direct::{Direct, RasterTarget};
use crate::iso::raymarch::Raymarch;
use crate::iso::PreparedVolume;
use crate::target::Target;
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};
use tessera_gpu::{Gpu, ShaderCompiler};

/// Each frame's isovalue as a fraction of the value range; `None` keeps it fixed.
type Sweep<'a> = Option<&'a dyn Fn(u32) -> f32>;

pub(crate) struct Techniques {
    pub(crate) raymarch: Raymarch,
    pub(crate) direct: Option<Direct>,
    pub(crate) direct_compute: Option<DirectCompute>,
}

pub(super) fn techniques(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    volume: &Volume,
    sink: &mut dyn RecordSink,
) -> Result<Techniques> {
    let scalar = volume.scalar_type();
    let direct = if gpu.caps().mesh_shader && gpu.caps().task_shader {
        Some(Direct::new(gpu, compiler, scalar)?)
    } else {
        sink.note(&format!(
            "{} has no task/mesh shaders; direct is skipped",
            gpu.caps().device_name
        ));
        None
    };
    let direct_compute = if gpu.caps().buffer_int64_atomics {
        Some(DirectCompute::new(gpu, compiler, scalar)?)
    } else {
        sink.note(&format!(
            "{} has no 64-bit buffer atomics; direct's compute path is skipped",
            gpu.caps().device_name
        ));
        None
    };
    Ok(Techniques {
        raymarch: Raymarch::new(gpu, compiler, scalar)?,
        direct,
        direct_compute,
    })
}

#[allow(clippy::too_many_arguments)]
fn measure(
    gpu: &Gpu,
    t: &Techniques,
    prepared: &PreparedVolume,
    volume: &Volume,
    (w, h): (u32, u32),
    scenario: &str,
    config: &BenchConfig,
    plan: FramePlan,
    sweep: Sweep,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let camera = OrbitCamera::default();
    let iso_of = |frame: u32| {
        let fraction = sweep.map_or(config.iso_fraction, |f| f(frame));
        volume.iso_to_texel(IsoValue::Normalized(fraction))
    };
    let record = |technique: &str, path: &str| {
        let mut r = BenchRecord::new(gpu, scenario, technique, path, volume.name());
        (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
        r
    };

    let target = Target::new(gpu, w, h)?;
    let mut frame = 0u32;
    let stages = time_frames(gpu, plan, 1, |rec, timer| {
        let params = Raymarch::params(prepared, iso_of(frame), &camera, w, h);
        frame += 1;
        timer.scope(rec, "raymarch", |rec| {
            t.raymarch.record(rec, prepared, &target, &params)
        });
    })?;
    drop(target);
    let mut r = record("raymarch", "compute");
    r.stages = stages;
    let raymarch_ms = r.median_ms("raymarch");
    sink.emit(&r)?;

    if let Some(direct) = &t.direct {
        for culling in [false, true] {
            let state = if culling {
                Some(CullState::new(gpu, prepared)?)
            } else {
                None
            };
            let target = RasterTarget::new(gpu, w, h)?;
            let capture = Direct::no_capture(gpu)?;
            let mut frame = 0u32;
            let mut recorded = Ok(());
            let stages = time_frames(gpu, plan, 1, |rec, timer| {
                let params = Direct::params(prepared, iso_of(frame), &camera, w, h, 0);
                frame += 1;
                let result = timer.scope(rec, "direct", |rec| {
                    direct.record(rec, prepared, &target, &params, &capture, state.as_ref())
                });
                recorded = recorded.clone().and(result.map_err(|e| e.to_string()));
            });
            let stats = direct.read_stats(gpu);
            let cull_stats = state.as_ref().map(|s| s.read_stats(gpu)).transpose();
            recorded.map_err(Error::Invalid)?;
            let (stats, cull_stats) = (stats?, cull_stats?);
            let mut r = record(if culling { "direct+roc" } else { "direct" }, "mesh");
            r.stages = stages?;
            r.counts
                .insert("triangles_last_frame".into(), stats.triangles as f64);
            r.counts.insert(
                "mesh_workgroups_last_frame".into(),
                stats.mesh_workgroups as f64,
            );
            if let Some(c) = cull_stats {
                r.counts
                    .insert("regions_occupied".into(), c.regions_occupied as f64);
                r.counts
                    .insert("blocks_visible".into(), c.blocks_visible as f64);
                r.counts.insert(
                    "blocks_drawn".into(),
                    (c.blocks_drawn_first + c.blocks_drawn_new) as f64,
                );
            }
            if let (Some(d), Some(rm)) = (r.median_ms("direct"), raymarch_ms) {
                r.counts.insert("speedup_over_raymarch".into(), rm / d);
            }
            sink.emit(&r)?;
        }
    }
    if let Some(compute) = &t.direct_compute {
        // Lists sized from the largest count over the isovalues this scenario visits.
        let probe = ComputeTarget::new(gpu, 1, 1, 1)?;
        let probe_pixels = Target::new(gpu, 1, 1)?;
        let mut most = 0u32;
        for frame in 0..64 {
            let params = Direct::params(prepared, iso_of(frame), &camera, 1, 1, 1);
            gpu.submit("count triangles", |rec| {
                compute.record(rec, prepared, &probe, &probe_pixels, &params)
            })?;
            most = most.max(compute.read_stats(gpu)?.triangles);
            if sweep.is_none() {
                break;
            }
        }
        drop((probe, probe_pixels));
        let capacity = most + most / 4 + 1024;
        let target = ComputeTarget::new(gpu, w, h, capacity)?;
        let pixels = Target::new(gpu, w, h)?;
        let mut frame = 0u32;
        let stages = time_frames(gpu, plan, 1, |rec, timer| {
            let params = Direct::params(prepared, iso_of(frame), &camera, w, h, capacity);
            frame += 1;
            timer.scope(rec, "direct", |rec| {
                compute.record(rec, prepared, &target, &pixels, &params)
            });
        });
        let stats = compute.read_stats(gpu)?;
        // The culled run below makes lists of the same capacity: free these first.
        drop(target);
        let mut r = record("direct", "compute");
        r.stages = stages?;
        r.counts
            .insert("triangles_last_frame".into(), stats.triangles as f64);
        r.counts
            .insert("blocks_classified".into(), stats.blocks_classified as f64);
        if let (Some(d), Some(rm)) = (r.median_ms("direct"), raymarch_ms) {
            r.counts.insert("speedup_over_raymarch".into(), rm / d);
        }
        sink.emit(&r)?;
        let mut r = record("direct+hzb", "compute");
        super::hzb::measure_compute_culled(
            gpu, compute, prepared, capacity, plan, &iso_of, &mut r,
        )?;
        if let (Some(d), Some(rm)) = (r.median_ms("direct"), raymarch_ms) {
            r.counts.insert("speedup_over_raymarch".into(), rm / d);
        }
        sink.emit(&r)?;
    }
    Ok(())
}

fn run_scenario(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
    scenario: &str,
    sweep: Sweep,
) -> Result<()> {
    let compiler = crate::shaders::compiler();
    for spec in bench_volumes(config) {
        let volume = make_volume(gpu, &spec, config)?;
        let t = techniques(gpu, &compiler, &volume, sink)?;
        let prepared = t.raymarch.prepare(gpu, &volume)?;
        let iso = volume.iso_to_texel(IsoValue::Normalized(config.iso_fraction));
        super::basic::settle(gpu, &t.raymarch, &prepared, iso)?;
        for size in bench_sizes(config) {
            measure(
                gpu, &t, &prepared, &volume, size, scenario, config, plan, sweep, sink,
            )?;
        }
    }
    Ok(())
}

/// `raymarch` against `direct` on the same volumes, sizes and camera.
pub fn isosurface(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    run_scenario(gpu, config, plan, sink, "isosurface", None)
}

/// The isovalue moves every frame, from 20 % to 60 % of the value range and back, as when a
/// user drags a slider: nothing may be precomputed per isovalue.
pub fn iso_sweep(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let period = 64u32;
    let sweep = move |frame: u32| {
        let phase = (frame % period) as f32 / period as f32;
        0.2 + 0.4 * (1.0 - (2.0 * phase - 1.0).abs())
    };
    run_scenario(gpu, config, plan, sink, "iso-sweep", Some(&sweep))
}

/// A new volume every frame, as when playing back a simulation's time steps: each frame copies
/// the next step from host memory into the volume texture, rebuilds the octree and renders.
/// The steps are the four procedural fields at one size and type, staged in host memory.
pub fn time_varying(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    use tessera_data::procedural::{generate, ProceduralKind};
    let compiler = crate::shaders::compiler();
    let sizes: &[(u32, ScalarType)] = if config.quick {
        &[(48, ScalarType::U8)]
    } else {
        &[(256, ScalarType::U8), (512, ScalarType::U8)]
    };
    let camera = OrbitCamera::default();
    for &(size, scalar) in sizes {
        let kinds = [
            ProceduralKind::HeadPhantom,
            ProceduralKind::Turbulence,
            ProceduralKind::MarschnerLobb,
            ProceduralKind::Sphere,
        ];
        let steps: Vec<Volume> = kinds
            .iter()
            .map(|&k| generate(k, size, scalar))
            .collect::<std::result::Result<_, _>>()?;
        let staged: Vec<_> = steps
            .iter()
            .map(|v| gpu.staging_with(v.name(), v.bytes()))
            .collect::<std::result::Result<_, _>>()?;
        let isos: Vec<f32> = steps
            .iter()
            .map(|v| v.iso_to_texel(IsoValue::Normalized(config.iso_fraction)))
            .collect();
        let t = techniques(gpu, &compiler, &steps[0], sink)?;
        let builder = crate::iso::minmax::MinMaxBuilder::new(gpu, &compiler, scalar)?;
        let prepared = PreparedVolume::new(gpu, &builder, &steps[0])?;
        // Each frame copies the next time step in and rebuilds the octree; returns its index.
        let next_step =
            |rec: &tessera_gpu::Recorder, timer: &mut tessera_gpu::Timer, frame: &mut usize| {
                let k = *frame % steps.len();
                *frame += 1;
                timer.scope(rec, "upload", |rec| {
                    rec.copy_buffer_to_image(&staged[k], &prepared.volume.texture)
                });
                rec.barrier();
                timer.scope(rec, "octree-build", |rec| {
                    builder.record(rec, &prepared.volume, &prepared.octree)
                });
                rec.barrier();
                k
            };
        let dataset = format!("{size}^3 {} x{} steps", scalar.name(), steps.len());
        for (w, h) in bench_sizes(config) {
            let mut frame = 0usize;
            let target = Target::new(gpu, w, h)?;
            let stages = time_frames(gpu, plan, 3, |rec, timer| {
                let k = next_step(rec, timer, &mut frame);
                let params = Raymarch::params(&prepared, isos[k], &camera, w, h);
                timer.scope(rec, "raymarch", |rec| {
                    t.raymarch.record(rec, &prepared, &target, &params)
                });
            })?;
            drop(target);
            let mut r = BenchRecord::new(gpu, "time-varying", "raymarch", "compute", &dataset);
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages);
            r.counts
                .insert("step_bytes".into(), steps[0].size_bytes() as f64);
            sink.emit(&r)?;
            if let Some(direct) = &t.direct {
                let target = RasterTarget::new(gpu, w, h)?;
                let capture = Direct::no_capture(gpu)?;
                let mut recorded = Ok(());
                let stages = time_frames(gpu, plan, 3, |rec, timer| {
                    let k = next_step(rec, timer, &mut frame);
                    let params = Direct::params(&prepared, isos[k], &camera, w, h, 0);
                    let result = timer.scope(rec, "direct", |rec| {
                        direct.record(rec, &prepared, &target, &params, &capture, None)
                    });
                    recorded = recorded.clone().and(result.map_err(|e| e.to_string()));
                });
                recorded.map_err(Error::Invalid)?;
                let mut r = BenchRecord::new(gpu, "time-varying", "direct", "mesh", &dataset);
                (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
                r.stages = stages?;
                r.counts
                    .insert("step_bytes".into(), steps[0].size_bytes() as f64);
                sink.emit(&r)?;
            }
            if let Some(compute) = &t.direct_compute {
                // Lists sized for the largest step's isosurface.
                let mut most = 0u32;
                let probe = ComputeTarget::new(gpu, 1, 1, 1)?;
                let probe_pixels = Target::new(gpu, 1, 1)?;
                for (k, step) in staged.iter().enumerate() {
                    let params = Direct::params(&prepared, isos[k], &camera, 1, 1, 1);
                    gpu.submit("count triangles", |rec| {
                        rec.copy_buffer_to_image(step, &prepared.volume.texture);
                        rec.barrier();
                        builder.record(rec, &prepared.volume, &prepared.octree);
                        rec.barrier();
                        compute.record(rec, &prepared, &probe, &probe_pixels, &params);
                    })?;
                    most = most.max(compute.read_stats(gpu)?.triangles);
                }
                drop((probe, probe_pixels));
                let capacity = most + most / 8 + 1024;
                let target = ComputeTarget::new(gpu, w, h, capacity)?;
                let pixels = Target::new(gpu, w, h)?;
                let stages = time_frames(gpu, plan, 3, |rec, timer| {
                    let k = next_step(rec, timer, &mut frame);
                    let params = Direct::params(&prepared, isos[k], &camera, w, h, capacity);
                    timer.scope(rec, "direct", |rec| {
                        compute.record(rec, &prepared, &target, &pixels, &params)
                    });
                });
                let mut r = BenchRecord::new(gpu, "time-varying", "direct", "compute", &dataset);
                (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
                r.stages = stages?;
                r.counts
                    .insert("step_bytes".into(), steps[0].size_bytes() as f64);
                sink.emit(&r)?;
            }
        }
    }
    Ok(())
}
