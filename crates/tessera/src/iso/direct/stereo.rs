//! Stereo pairs in one pass with multiview (paper D §4.1.3): the task stage runs once, and the
//! mesh and fragment stages take each view's projection and eye from a small buffer by
//! `gl_ViewIndex`. Needs `multiviewMeshShader`; without it render the eyes one after the other.

use crate::builtin_shader;
use crate::config::volume_defines;
use crate::error::{Error, Result};
use crate::iso::direct::{Direct, DirectParams, RasterTarget, COLOR_FORMAT, DEPTH_FORMAT};
use crate::iso::PreparedVolume;
use tessera_data::shading::BACKGROUND;
use tessera_data::ScalarType;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, Pipeline, Recorder, RenderTargets, ShaderCompiler, Slot,
};

pub struct DirectMultiview {
    pipeline: Pipeline,
}

impl DirectMultiview {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
    ) -> Result<DirectMultiview> {
        if !gpu.caps().mesh_multiview {
            return Err(Error::Invalid(format!(
                "{} cannot use multiview with mesh shaders; render the eyes one after the other",
                gpu.caps().device_name
            )));
        }
        let mut defines = volume_defines(scalar);
        defines.push(("MULTIVIEW".into(), "1".into()));
        defines.push(("BLOCK_LIST".into(), "0".into()));
        let task = compiler.compile(&builtin_shader!("direct.task.glsl"), &defines)?;
        let mesh = compiler.compile(&builtin_shader!("direct.mesh.glsl"), &defines)?;
        let frag = compiler.compile(&builtin_shader!("direct.frag.glsl"), &defines)?;
        let targets = RenderTargets {
            views: 2,
            ..RenderTargets::color_depth(COLOR_FORMAT, DEPTH_FORMAT)
        };
        let mut slots = vec![Slot::Texture];
        slots.extend([Slot::StorageBuffer; 5]);
        let pipeline = gpu.graphics_pipeline_for(
            "direct isosurface (multiview)",
            &[&task, &mesh, &frag],
            &slots,
            &targets,
        )?;
        Ok(DirectMultiview { pipeline })
    }

    /// The per-view data (`iso/direct/views.glsl`) of the two eyes.
    pub fn views_buffer(gpu: &Gpu, eyes: &[DirectParams; 2]) -> Result<Buffer> {
        let mut data: Vec<f32> = Vec::with_capacity(40);
        for e in eyes {
            data.extend(e.grid_to_clip.iter().flatten());
        }
        for e in eyes {
            data.extend([e.eye_world[0], e.eye_world[1], e.eye_world[2], 0.0]);
        }
        Ok(gpu.upload_buffer(
            "direct views",
            bytemuck::cast_slice(&data),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?)
    }

    /// Records both eyes into the two layers of `target` (made with
    /// [`RasterTarget::with_views`]); `params` supplies the isovalue, light and volume.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        rec: &Recorder,
        direct: &Direct,
        prepared: &PreparedVolume,
        target: &RasterTarget,
        params: &DirectParams,
        views: &Buffer,
        capture: &Buffer,
    ) -> Result<()> {
        direct.record_stats_reset(rec);
        rec.discard_to_general(&target.color);
        rec.discard_to_general(&target.depth);
        rec.begin_rendering_with_depth(&target.color, Some(&target.depth), BACKGROUND);
        let [tex, nodes, stats, capture_binding, _] = direct.bindings(prepared, capture, capture);
        let drawn = rec.draw_mesh_tasks(
            &self.pipeline,
            &[
                tex,
                nodes,
                stats,
                capture_binding,
                Binding::Buffer(capture),
                Binding::Buffer(views),
            ],
            bytemuck::bytes_of(params),
            prepared.octree.level_dims[0],
        );
        rec.end_rendering();
        rec.barrier();
        Ok(drawn?)
    }
}
