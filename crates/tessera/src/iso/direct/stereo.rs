//! Stereo pairs in one pass with multiview (paper D §4.1.3): the task stage runs once, and the
//! mesh and fragment stages take each view's projection and eye from a small buffer by
//! `gl_ViewIndex`. Needs `multiviewMeshShader`; without it render the eyes one after the other.

use crate::builtin_shader;
use crate::config::marching_cubes_defines;
use crate::error::{Error, Result};
use crate::iso::direct::{Direct, DirectParams, RasterTarget, COLOR_FORMAT, DEPTH_FORMAT};
use crate::iso::PreparedVolume;
use bytemuck::{Pod, Zeroable};
use std::mem::size_of;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::shading::BACKGROUND;
use tessera_data::ScalarType;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, RenderTargets, ShaderCompiler,
    Slot,
};

/// The two eyes' projections and positions, as `views.glsl` reads them by `gl_ViewIndex`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct StereoViews {
    pub grid_to_clip: [[[f32; 4]; 4]; 2],
    pub eye_world: [[f32; 4]; 2],
}

impl StereoViews {
    pub fn of(eyes: &[DirectParams; 2]) -> StereoViews {
        StereoViews {
            grid_to_clip: eyes.map(|e| e.grid_to_clip),
            eye_world: eyes.map(|e| [e.eye_world[0], e.eye_world[1], e.eye_world[2], 0.0]),
        }
    }
}

/// The multiview pipeline and its per-view buffer, written in the command stream each frame.
pub struct DirectMultiview {
    pipeline: Pipeline,
    views: Buffer,
}
impl DirectMultiview {
    /// The multiview pipeline with ambiguous faces cut by the asymptotic decider.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
    ) -> Result<DirectMultiview> {
        Self::with_rule(gpu, compiler, scalar, AmbiguityRule::default())
    }

    /// The multiview pipeline with ambiguous faces cut by `rule`.
    pub fn with_rule(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
    ) -> Result<DirectMultiview> {
        if !gpu.caps().mesh_multiview {
            return Err(Error::Invalid(format!(
                "{} cannot use multiview with mesh shaders; render the eyes one after the other",
                gpu.caps().device_name
            )));
        }
        let mut defines = marching_cubes_defines(scalar, rule);
        defines.push(("MULTIVIEW".into(), "1".into()));
        defines.push(("BLOCK_LIST".into(), "0".into()));
        let task = compiler.compile(&builtin_shader!("direct.task.glsl"), &defines)?;
        let mesh = compiler.compile(&builtin_shader!("direct.mesh.glsl"), &defines)?;
        let frag = compiler.compile(&builtin_shader!("direct.frag.glsl"), &defines)?;
        let targets = RenderTargets {
            views: 2,
            dynamic_cull_mode: true,
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
        let views = gpu.create_buffer(
            "direct views",
            size_of::<StereoViews>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(DirectMultiview { pipeline, views })
    }

    /// Records both eyes into the two layers of `target` (made with
    /// [`RasterTarget::with_views`]); the first eye's parameters supply the isovalue, light and
    /// volume. The side of a closed surface neither eye can see is culled
    /// ([`Direct::pair_hidden_winding`]).
    pub fn record(
        &self,
        rec: &Recorder,
        direct: &Direct,
        prepared: &PreparedVolume,
        target: &RasterTarget,
        eyes: &[DirectParams; 2],
        capture: &Buffer,
    ) -> Result<()> {
        rec.update_buffer(&self.views, bytemuck::bytes_of(&StereoViews::of(eyes)));
        direct.record_stats_reset(rec);
        rec.discard_to_general(&target.color);
        rec.discard_to_general(&target.depth);
        rec.begin_rendering_with_depth(&target.color, Some(&target.depth), BACKGROUND);
        rec.set_cull_mode(Direct::cull_mode_of(Direct::pair_hidden_winding(
            prepared, eyes,
        )));
        let [tex, nodes, stats, capture_binding, _] = direct.bindings(prepared, capture, capture);
        let drawn = rec.draw_mesh_tasks(
            &self.pipeline,
            &[
                tex,
                nodes,
                stats,
                capture_binding,
                Binding::Buffer(capture),
                Binding::Buffer(&self.views),
            ],
            bytemuck::bytes_of(&eyes[0]),
            prepared.octree.level_dims[0],
        );
        rec.end_rendering();
        rec.barrier();
        Ok(drawn?)
    }
}
