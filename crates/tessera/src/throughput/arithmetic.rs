//! Per-pixel arithmetic: `busy_work` once per pixel, from a fragment shader over a full-screen
//! triangle ("fragment") or from a compute shader ("compute"), into the same kind of RGBA8
//! target. The graphics path pays for rasterization setup, fragment scheduling and colour output;
//! on GPUs whose graphics stages run on a few units only, that is where the difference shows.

use super::{create_target, record, shader_defines, ThroughputOptions, TARGET_FORMAT};
use crate::bench::{time_frames, BenchRecord};
use crate::builtin_shader;
use crate::error::Result;
use bytemuck::{Pod, Zeroable};
use tessera_gpu::{Binding, Gpu, Image, Pipeline, Recorder, ShaderCompiler, Slot};

/// The `technique` field of the records.
pub const TECHNIQUE: &str = "arithmetic";

/// Push constants of `busy.frag.glsl` and `busy.comp.glsl` (their `ArithmeticParams` block; a
/// test holds the layouts together).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ArithmeticParams {
    pub size: [u32; 2],
    pub iterations: u32,
}

/// The two pipelines that evaluate `busy_work`.
pub struct Arithmetic {
    fragment: Pipeline,
    compute: Pipeline,
}

impl Arithmetic {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<Arithmetic> {
        let defines = shader_defines();
        let vert = compiler.compile(&builtin_shader!("fullscreen.vert.glsl"), &defines)?;
        let frag = compiler.compile(&builtin_shader!("busy.frag.glsl"), &defines)?;
        let comp = compiler.compile(&builtin_shader!("busy.comp.glsl"), &defines)?;
        let fragment = gpu.graphics_pipeline(
            "throughput busy fragment",
            &[&vert, &frag],
            &[],
            TARGET_FORMAT,
            false,
        )?;
        let compute =
            gpu.compute_pipeline("throughput busy compute", &comp, &[Slot::StorageImage])?;
        Ok(Arithmetic { fragment, compute })
    }

    fn params(target: &Image, iterations: u32) -> ArithmeticParams {
        ArithmeticParams {
            size: [target.extent.width, target.extent.height],
            iterations,
        }
    }

    /// Renders `busy_work` into every pixel of `target` (in `GENERAL` layout). The render pass
    /// clears first (the recorder's only load operation); a clear is cheap next to the shading.
    pub fn record_fragment(&self, rec: &Recorder, target: &Image, iterations: u32) {
        let params = Self::params(target, iterations);
        rec.begin_rendering(target, [0.0; 4]);
        rec.draw(&self.fragment, &[], bytemuck::bytes_of(&params), 3);
        rec.end_rendering();
    }

    /// Stores `busy_work` into every pixel of `target` (in `GENERAL` layout).
    pub fn record_compute(&self, rec: &Recorder, target: &Image, iterations: u32) {
        let params = Self::params(target, iterations);
        rec.dispatch(
            &self.compute,
            &[Binding::StorageImage(target)],
            bytemuck::bytes_of(&params),
            [target.extent.width, target.extent.height, 1],
        );
    }
}

/// Times both paths, fragment first, and returns their records.
pub fn measure(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    opts: &ThroughputOptions,
) -> Result<Vec<BenchRecord>> {
    let arithmetic = Arithmetic::new(gpu, compiler)?;
    let target = create_target(gpu, "throughput busy target", opts.width, opts.height)?;
    let mut records = Vec::new();
    for path in ["fragment", "compute"] {
        let stages = time_frames(gpu, opts.plan, 1, |rec, timer| {
            // Each frame overwrites every pixel, so the old contents may go.
            rec.discard_to_general(&target);
            timer.scope(rec, TECHNIQUE, |rec| match path {
                "fragment" => arithmetic.record_fragment(rec, &target, opts.iterations),
                _ => arithmetic.record_compute(rec, &target, opts.iterations),
            });
        })?;
        let mut r = record(
            gpu,
            opts,
            TECHNIQUE,
            path,
            format!("busy_work x{}", opts.iterations),
        );
        let pixels = f64::from(opts.width) * f64::from(opts.height);
        r.counts.insert("pixels".into(), pixels);
        r.counts
            .insert("iterations".into(), f64::from(opts.iterations));
        if let Some(ms) = stages.first().map(|s| s.median_ms) {
            r.counts
                .insert("gpix_per_s".into(), pixels / (ms * 1e-3) / 1e9);
        }
        r.stages = stages;
        records.push(r);
    }
    Ok(records)
}
