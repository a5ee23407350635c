//! An exclusive prefix sum of a buffer of counts on the GPU, in place (`exclusive_scan.comp.glsl`):
//! the step between counting items per bucket and scattering them into per-bucket lists.

use crate::builtin_shader;
use crate::error::Result;
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// Invocations of the one workgroup that scans.
const SCAN_WORKGROUP: u32 = 256;

pub struct ExclusiveScan {
    pipeline: Pipeline,
}

impl ExclusiveScan {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<ExclusiveScan> {
        let defines = [("SCAN_WORKGROUP".to_string(), SCAN_WORKGROUP.to_string())];
        let spirv = compiler.compile(&builtin_shader!("exclusive_scan.comp.glsl"), &defines)?;
        let pipeline = gpu.compute_pipeline("exclusive scan", &spirv, &[Slot::StorageBuffer])?;
        Ok(ExclusiveScan { pipeline })
    }

    /// Replaces the first `count` words of `values` by their exclusive prefix sums; ends with a
    /// barrier.
    pub fn record(&self, rec: &Recorder, values: &Buffer, count: u32) {
        rec.dispatch_groups(
            &self.pipeline,
            &[Binding::Buffer(values)],
            bytemuck::bytes_of(&count),
            [1, 1, 1],
        );
        rec.barrier();
    }
}
