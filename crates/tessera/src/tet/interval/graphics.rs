//! The graphics path of interval shading (paper A): a mesh shader emits each tet's proxies and
//! the rasterizer hands every fragment its interval; fragments blend into a float attachment.

use super::mesh::{GpuTetMesh, OPTICAL_FORMAT};
use super::IntervalParams;
use crate::builtin_shader;
use crate::error::{Error, Result};
use tessera_gpu::{
    Binding, Blend, Gpu, Image, Pipeline, Recorder, RenderTargets, ShaderCompiler, Slot,
};

/// Largest tets per mesh workgroup: 16 × 15 vertices and 16 × 12 triangles stay within the
/// output limits every mesh-shader device offers (256 each).
pub const MAX_TETS_PER_WORKGROUP: u32 = 16;

pub struct IntervalGraphics {
    pipeline: Pipeline,
    tets_per_workgroup: u32,
}

impl IntervalGraphics {
    /// `defines` are the technique's; `maximum` blends by maximum instead of adding.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        tets_per_workgroup: u32,
        maximum: bool,
    ) -> Result<IntervalGraphics> {
        if !gpu.caps().mesh_shader {
            return Err(Error::Invalid(format!(
                "interval shading's graphics path needs mesh shaders, which {} lacks",
                gpu.caps().device_name
            )));
        }
        if !(1..=MAX_TETS_PER_WORKGROUP).contains(&tets_per_workgroup) {
            return Err(Error::Invalid(format!(
                "tets per mesh workgroup must be 1 to {MAX_TETS_PER_WORKGROUP}, not {tets_per_workgroup}"
            )));
        }
        let mut defines = defines.to_vec();
        defines.push(("GROUP".into(), tets_per_workgroup.to_string()));
        let mesh = compiler.compile(&builtin_shader!("interval.mesh.glsl"), &defines)?;
        let frag = compiler.compile(&builtin_shader!("interval.frag.glsl"), &defines)?;
        let targets = RenderTargets {
            blend: if maximum { Blend::Max } else { Blend::Add },
            ..RenderTargets::color(OPTICAL_FORMAT)
        };
        let pipeline = gpu.graphics_pipeline_for(
            "interval shading",
            &[&mesh, &frag],
            &[Slot::StorageBuffer; super::COMMON_BINDINGS],
            &targets,
        )?;
        Ok(IntervalGraphics {
            pipeline,
            tets_per_workgroup,
        })
    }

    /// Records one frame into `image` (cleared first); `common` are the technique's first
    /// bindings (`buffers.glsl`).
    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        common: &[Binding],
        image: &Image,
        params: &IntervalParams,
    ) -> Result<()> {
        rec.discard_to_general(image);
        rec.begin_rendering(image, [0.0; 4]);
        let drawn = rec.draw_mesh_tasks(
            &self.pipeline,
            common,
            bytemuck::bytes_of(params),
            // Mesh dispatch limits are not in the capabilities; stay within the guaranteed minimum.
            tessera_gpu::spread_groups(
                mesh.tet_count.div_ceil(self.tets_per_workgroup),
                tessera_gpu::pipeline::MIN_GROUPS_PER_AXIS,
            ),
        );
        rec.end_rendering();
        rec.barrier();
        Ok(drawn?)
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_pipeline(self.pipeline);
    }
}
