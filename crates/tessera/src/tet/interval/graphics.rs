//! The graphics path of interval shading (paper A): a mesh shader emits each tet's proxies and
//! the rasterizer hands every fragment its interval; fragments blend into a float attachment.

use super::mesh::{GpuTetMesh, DEPTH_FORMAT, OPTICAL_FORMAT};
use super::IntervalParams;
use crate::builtin_shader;
use crate::error::{Error, Result};
use tessera_gpu::{
    Binding, Blend, Gpu, Image, Pipeline, Recorder, RenderTargets, ShaderCompiler, Slot,
};

/// Largest tets per mesh workgroup: 16 × 15 vertices and 16 × 12 triangles stay within the
/// output limits every mesh-shader device offers (256 each).
pub const MAX_TETS_PER_WORKGROUP: u32 = 16;

/// How fragments combine in the attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Combine {
    Add,
    Max,
    /// Depth-tested: the nearest fragment stays (the asteroid field).
    Nearest,
}

pub struct IntervalGraphics {
    pipeline: Pipeline,
    tets_per_workgroup: u32,
}

impl IntervalGraphics {
    /// `defines` are the technique's.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        defines: &[(String, String)],
        tets_per_workgroup: u32,
        combine: Combine,
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
        let targets = match combine {
            Combine::Add => RenderTargets {
                blend: Blend::Add,
                ..RenderTargets::color(OPTICAL_FORMAT)
            },
            Combine::Max => RenderTargets {
                blend: Blend::Max,
                ..RenderTargets::color(OPTICAL_FORMAT)
            },
            Combine::Nearest => RenderTargets::color_depth(OPTICAL_FORMAT, DEPTH_FORMAT),
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

    /// Records one frame into `image` and `depth` (cleared first; `depth` for
    /// [`Combine::Nearest`] only); `common` are the technique's first bindings (`buffers.glsl`).
    pub fn record(
        &self,
        rec: &Recorder,
        mesh: &GpuTetMesh,
        common: &[Binding],
        (image, depth): (&Image, Option<&Image>),
        params: &IntervalParams,
    ) -> Result<()> {
        rec.discard_to_general(image);
        if let Some(d) = depth {
            rec.discard_to_general(d);
        }
        rec.begin_rendering_with_depth(image, depth, [0.0; 4]);
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
}
