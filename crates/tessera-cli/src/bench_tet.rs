//! Tetrahedral-mesh benchmark scenarios.

use crate::bench::{BenchArgs, Sink};
use anyhow::Result;
use tessera::bench::{time_frames, BenchRecord, FramePlan};
use tessera::tet::interval::compute::{IntervalCompute, OpticalBuffer};
use tessera::tet::interval::{GpuTetMesh, Interval, OpticalTarget};
use tessera_data::tet::procedural::box_mesh;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// Interval shading of procedural tet boxes of about 61 k, 959 k and 2.4 M tets (the sizes of
/// paper A's Table 1), far, close and inside views, at 3840×2160 (`--quick`: small meshes and image).
pub fn interval(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    let compiler = tessera::shaders::compiler();
    if !gpu.caps().mesh_shader {
        println!(
            "note: {} has no mesh shaders; interval is skipped",
            gpu.caps().device_name
        );
        return Ok(());
    }
    let interval = Interval::new(gpu, &compiler)?;
    let compute = if gpu.caps().buffer_float32_atomic_add {
        Some(IntervalCompute::new(gpu, &compiler)?)
    } else {
        None
    };
    let (w, h) = if args.quick { (256, 144) } else { (3840, 2160) };
    // n³ cells of 6 tets each.
    let cells: &[u32] = if args.quick { &[6, 10] } else { &[22, 54, 74] };
    let views = [("far", 2.4f32), ("close", 1.4), ("inside", 0.3)];
    for &n in cells {
        let mesh = box_mesh(n);
        let gpu_mesh = GpuTetMesh::upload(gpu, &mesh)?;
        let target = OpticalTarget::new(gpu, w, h)?;
        let buffer = OpticalBuffer::new(gpu, w, h)?;
        for (view, distance) in views {
            let camera = OrbitCamera {
                distance,
                ..OrbitCamera::default()
            };
            let params = Interval::params(&gpu_mesh, &camera, w, h);
            let mut recorded = Ok(());
            let stages = time_frames(gpu, plan, 1, |rec, timer| {
                let r = timer.scope(rec, "interval", |rec| {
                    interval.record(rec, &gpu_mesh, &target, &params)
                });
                recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
            });
            recorded.map_err(anyhow::Error::msg)?;
            let dataset = format!("box {} tets, {view}", mesh.tets.len());
            let mut r = BenchRecord::new(gpu, "interval", "interval", "mesh", &dataset);
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages?);
            r.counts.insert("tets".into(), mesh.tets.len() as f64);
            if let Some(ms) = r.median_ms("interval") {
                r.counts
                    .insert("mtets_per_s".into(), mesh.tets.len() as f64 / ms / 1e3);
            }
            sink.emit(&r)?;
            if let Some(compute) = &compute {
                let mut recorded = Ok(());
                let stages = time_frames(gpu, plan, 1, |rec, timer| {
                    let r = timer.scope(rec, "interval", |rec| {
                        compute.record(rec, &gpu_mesh, &buffer, &params)
                    });
                    recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
                });
                recorded.map_err(anyhow::Error::msg)?;
                let mut r = BenchRecord::new(gpu, "interval", "interval", "compute", &dataset);
                (r.width, r.height, r.warmup, r.frames, r.stages) =
                    (w, h, plan.warmup, plan.frames, stages?);
                r.counts.insert("tets".into(), mesh.tets.len() as f64);
                sink.emit(&r)?;
            }
        }
        buffer.destroy(gpu);
        target.destroy(gpu);
        gpu_mesh.destroy(gpu);
    }
    interval.destroy(gpu);
    if let Some(c) = compute {
        c.destroy(gpu);
    }
    Ok(())
}
