//! Indirect dispatch arguments from a count a GPU pass wrote: one workgroup per `group_size`
//! items, on a 2-D grid of workgroups where one row would exceed the device's limit (the pass
//! flattens the grid again). Counts buffer layout: `uint count; uint dispatch[3];`.

use crate::builtin_shader;
use crate::error::Result;
use bytemuck::{Pod, Zeroable};
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// Push constants of `raster_prepare.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct PrepareParams {
    pub(crate) max_groups: [u32; 2],
    pub(crate) group_size: u32,
    pub(crate) _pad: u32,
}

pub struct IndirectArgs {
    pipeline: Pipeline,
    /// Workgroups allowed along x and y.
    pub max_groups: [u32; 2],
}

impl IndirectArgs {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<IndirectArgs> {
        let spirv = compiler.compile(&builtin_shader!("raster_prepare.comp.glsl"), &[])?;
        let pipeline =
            gpu.compute_pipeline("indirect arguments", &spirv, &[Slot::StorageBuffer])?;
        let limit = gpu.caps().max_compute_workgroup_count;
        Ok(IndirectArgs {
            pipeline,
            max_groups: [limit[0], limit[1]],
        })
    }

    /// Writes `counts`' dispatch arguments for `group_size` items per workgroup; ends with a
    /// barrier.
    pub fn record(&self, rec: &Recorder, counts: &Buffer, group_size: u32) {
        let params = PrepareParams {
            max_groups: self.max_groups,
            group_size,
            _pad: 0,
        };
        rec.dispatch_groups(
            &self.pipeline,
            &[Binding::Buffer(counts)],
            bytemuck::bytes_of(&params),
            [1, 1, 1],
        );
        rec.barrier();
    }
}
