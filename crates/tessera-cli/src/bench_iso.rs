//! Isosurface benchmark scenarios that set techniques side by side in one run.

use crate::bench::{bench_sizes, bench_volumes, make_volume, BenchArgs, Sink};
use anyhow::Result;
use tessera::bench::{time_frames, BenchRecord, FramePlan};
use tessera::iso::direct::{Direct, RasterTarget};
use tessera::iso::raymarch::Raymarch;
use tessera::iso::PreparedVolume;
use tessera::target::PixelTarget;
use tessera_data::{IsoValue, OrbitCamera, Volume};
use tessera_gpu::{Gpu, ShaderCompiler};

/// Each frame's isovalue as a fraction of the value range; `None` keeps it fixed.
type Sweep<'a> = Option<&'a dyn Fn(u32) -> f32>;

struct Techniques {
    raymarch: Raymarch,
    direct: Option<Direct>,
}

fn techniques(gpu: &Gpu, compiler: &ShaderCompiler, volume: &Volume) -> Result<Techniques> {
    let scalar = volume.scalar_type();
    let direct = if gpu.caps().mesh_shader && gpu.caps().task_shader {
        Some(Direct::new(gpu, compiler, scalar)?)
    } else {
        println!(
            "note: {} has no task/mesh shaders; direct is skipped",
            gpu.caps().device_name
        );
        None
    };
    Ok(Techniques {
        raymarch: Raymarch::new(gpu, compiler, scalar)?,
        direct,
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
    args: &BenchArgs,
    plan: FramePlan,
    sweep: Sweep,
    sink: &mut Sink,
) -> Result<()> {
    let camera = OrbitCamera::default();
    let iso_of = |frame: u32| {
        let fraction = sweep.map_or(args.iso_fraction, |f| f(frame));
        volume.iso_to_texel(IsoValue::Normalized(fraction))
    };
    let record = |technique: &str, path: &str| {
        let mut r = BenchRecord::new(gpu, scenario, technique, path, volume.name());
        (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
        r
    };

    let target = PixelTarget::new(gpu, w, h)?;
    let mut frame = 0u32;
    let stages = time_frames(gpu, plan, 1, |rec, timer| {
        let params = Raymarch::params(prepared, iso_of(frame), &camera, w, h);
        frame += 1;
        timer.scope(rec, "raymarch", |rec| {
            t.raymarch.record(rec, prepared, &target, &params)
        });
    })?;
    target.destroy(gpu);
    let mut r = record("raymarch", "compute");
    r.stages = stages;
    let raymarch_ms = r.median_ms("raymarch");
    sink.emit(&r)?;

    if let Some(direct) = &t.direct {
        let target = RasterTarget::new(gpu, w, h)?;
        let capture = Direct::no_capture(gpu)?;
        let mut frame = 0u32;
        let mut recorded = Ok(());
        let stages = time_frames(gpu, plan, 1, |rec, timer| {
            let params = Direct::params(prepared, iso_of(frame), &camera, w, h, 0);
            frame += 1;
            let result = timer.scope(rec, "direct", |rec| {
                direct.record(rec, prepared, &target, &params, &capture)
            });
            recorded = recorded.clone().and(result.map_err(|e| e.to_string()));
        });
        let stats = direct.read_stats(gpu);
        target.destroy(gpu);
        gpu.destroy_buffer(capture);
        recorded.map_err(anyhow::Error::msg)?;
        let stats = stats?;
        let mut r = record("direct", "mesh");
        r.stages = stages?;
        r.counts
            .insert("triangles_last_frame".into(), stats.triangles as f64);
        r.counts.insert(
            "mesh_workgroups_last_frame".into(),
            stats.mesh_workgroups as f64,
        );
        if let (Some(d), Some(rm)) = (r.median_ms("direct"), raymarch_ms) {
            r.counts.insert("speedup_over_raymarch".into(), rm / d);
        }
        sink.emit(&r)?;
    }
    Ok(())
}

fn run_scenario(
    gpu: &Gpu,
    args: &BenchArgs,
    plan: FramePlan,
    sink: &mut Sink,
    scenario: &str,
    sweep: Sweep,
) -> Result<()> {
    let compiler = tessera::shaders::compiler();
    for spec in bench_volumes(args) {
        let volume = make_volume(gpu, &spec, args)?;
        let t = techniques(gpu, &compiler, &volume)?;
        let prepared = t.raymarch.prepare(gpu, &volume)?;
        for size in bench_sizes(args.quick) {
            measure(
                gpu, &t, &prepared, &volume, size, scenario, args, plan, sweep, sink,
            )?;
        }
        prepared.destroy(gpu);
        t.raymarch.destroy(gpu);
        if let Some(d) = t.direct {
            d.destroy(gpu);
        }
    }
    Ok(())
}

/// `raymarch` against `direct` on the same volumes, sizes and camera.
pub fn isosurface(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    run_scenario(gpu, args, plan, sink, "isosurface", None)
}

/// The isovalue moves every frame, from 20 % to 60 % of the value range and back, as when a
/// user drags a slider: nothing may be precomputed per isovalue.
pub fn iso_sweep(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    let period = 64u32;
    let sweep = move |frame: u32| {
        let phase = (frame % period) as f32 / period as f32;
        0.2 + 0.4 * (1.0 - (2.0 * phase - 1.0).abs())
    };
    run_scenario(gpu, args, plan, sink, "iso-sweep", Some(&sweep))
}
