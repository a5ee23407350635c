//! `param-tess`: the TESSELLATION-BASED variant of paper E (Unterguggenberger et al. 2024, §4.2):
//! the LOD stage's patches to render ([`super::lod`]) drawn with hardware tessellation, one quad
//! patch per patch to render, into a colour and depth attachment.
//!
//! Passes per frame, all recorded into one command buffer with no read-back:
//! 1. the LOD stage (`param-points`' own, unchanged);
//! 2. `tess_args.comp`: the indirect draw's arguments from the LOD stage's render count (clamped
//!    to the list's capacity): one vertex per patch, in instances of
//!    [`ParamTess::patches_per_instance`] vertices (all of them in one, except on lavapipe);
//! 3. one indirect draw: `tess.vert` (the patch's index; a patch has one control point),
//!    `tess.tesc` (levels, below), `tess.tese` (vertex = `f(u, v)` over the patch's ranges,
//!    projected with [`View`]'s `world_to_clip`), `tess.frag` (shading of `param/shade.glsl`,
//!    the point variant's resolve: normal from the function, Lambert + ambient, glyphs coloured by
//!    direction), depth-tested (LESS); with MSAA into multisampled attachments averaged into a
//!    single-sample one when rendering ends, shaded once per pixel at the covered samples'
//!    centroid;
//! 4. `tess_downsample.comp`: each image pixel the average of its `k × k` raster pixels
//!    (supersampling `k`), packed into the [`Target`] the point variant also writes.
//!
//! Tessellation levels ([`TessLevels`]): fixed, every level `l`; or adaptive, each level the
//! screen length it subdivides over [`TessLevels::Adaptive::pixels_per_segment`] `p`,
//! `clamp(ceil(e / p), l_min, l_max)`: the inner levels from the patch's extents `(e_u, e_v)`
//! that the LOD stage measured (paper E's rule, which with `l' = e · l / min(t, l)` is this one
//! for `p = min(t, l) / l`, i.e. `p = 1` in all its configurations), the outer ones from the
//! edge's own screen length measured on 8 points in the control shader. The paper uses the
//! extents for every level; measuring edges instead makes two patches that share a whole edge
//! choose the same level, so that they meet without cracks (T-junctions where the LOD split one
//! side and not the other still leave sub-pixel gaps at coarse levels). `l_min = 8` and
//! `l_max = 64` as in the paper, the latter never above the device's limit.
//!
//! Changes from the paper: the per-edge outer levels above; MSAA is resolved by the attachment's
//! averaging resolve and supersampling by a compute pass, both into the packed RGBA8 frame.

mod frame;
mod options;

pub use frame::TessFrame;
pub use options::{ParamTessOptions, TessLevels, DEFAULT_MAX_LEVEL, DEFAULT_MIN_LEVEL};

use super::lod::{GpuPatch, LodSettings, LodStage};
use super::points::points_defines;
use super::scene::GpuParamScene;
use super::ParamFrameInfo;
use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_data::View;
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, RenderTargets, ShaderCompiler,
    Slot, Timer,
};

/// Colour attachment: float, so that MSAA and supersampling average unrounded colours as the
/// reference does before its one rounding to 8 bits.
pub const COLOR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Push constants of the drawing stages (`param/tess_params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct TessParams {
    pub world_to_clip: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub light: [f32; 4],
    pub viewport: [f32; 2],
    pub pixels_per_segment: f32,
    pub fixed_level: f32,
    pub min_level: f32,
    pub max_level: f32,
    pub render_capacity: u32,
    pub patches_per_instance: u32,
}

/// Push constants of `tess_args.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ArgsParams {
    pub render_capacity: u32,
    pub patches_per_instance: u32,
}

/// Push constants of `tess_downsample.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct DownsampleParams {
    pub size: [u32; 2],
    pub supersample: u32,
}

pub struct ParamTess {
    lod: LodStage,
    args: Pipeline,
    draw: Pipeline,
    downsample: Pipeline,
    /// The indirect draw's `VkDrawIndirectCommand`, written by `tess_args` each frame.
    draw_args: Buffer,
    /// Patches per instance of the draw (module documentation).
    patches_per_instance: u32,
    options: ParamTessOptions,
}

impl ParamTess {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        options: ParamTessOptions,
    ) -> Result<ParamTess> {
        options::check_options(gpu, &options)?;
        let mut defines = points_defines();
        if options.debug_levels {
            defines.push(("TESS_DEBUG_LEVELS".into(), "1".into()));
        }
        let spirv = |source| compiler.compile(&source, &defines);
        let shaders = [
            spirv(builtin_shader!("tess.vert.glsl"))?,
            spirv(builtin_shader!("tess.tesc.glsl"))?,
            spirv(builtin_shader!("tess.tese.glsl"))?,
            spirv(builtin_shader!("tess.frag.glsl"))?,
        ];
        let args = spirv(builtin_shader!("tess_args.comp.glsl"))?;
        let downsample = spirv(builtin_shader!("tess_downsample.comp.glsl"))?;
        let lod = LodStage::new(
            gpu,
            compiler,
            LodSettings {
                thresholds: options.thresholds,
                max_steps: options.max_steps,
                frustum_culling: options.frustum_culling,
                capacity: options.patch_capacity,
                pre_split: options.pre_split,
            },
        )?;
        let args = gpu.compute_pipeline("param tess args", &args, &[Slot::StorageBuffer; 2])?;
        let targets = RenderTargets {
            samples: options.msaa,
            patch_control_points: 1,
            ..RenderTargets::color_depth(COLOR_FORMAT, DEPTH_FORMAT)
        };
        let stages: Vec<_> = shaders.iter().collect();
        let draw = gpu.graphics_pipeline_for(
            "param tess draw",
            &stages,
            &[Slot::StorageBuffer; 5],
            &targets,
        )?;
        let downsample = gpu.compute_pipeline(
            "param tess downsample",
            &downsample,
            &[Slot::StorageImage, Slot::StorageBuffer],
        )?;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let draw_args =
            gpu.create_buffer("param tess draw args", 16, usage, MemoryLocation::GpuOnly)?;
        Ok(ParamTess {
            lod,
            args,
            draw,
            downsample,
            draw_args,
            patches_per_instance: options::patches_per_instance(gpu, &options),
            options,
        })
    }

    /// The LOD stage's counters of the last frame.
    pub fn read_lod_stats(&self, gpu: &Gpu) -> Result<super::lod::LodStats> {
        self.lod.read_stats(gpu)
    }

    pub fn options(&self) -> &ParamTessOptions {
        &self.options
    }

    /// Patches one instance of the draw holds on this device.
    pub fn patches_per_instance(&self) -> u32 {
        self.patches_per_instance
    }

    /// The view of `camera` onto `scene` at `size` with this technique's supersampling.
    pub fn view(
        &self,
        scene: &GpuParamScene,
        camera: &OrbitCamera,
        size: (u32, u32),
    ) -> Result<View> {
        scene.view(camera, size, self.options.supersample)
    }

    /// A frame for `view` with this technique's multisampling.
    pub fn frame(&self, gpu: &Gpu, view: &View) -> Result<TessFrame> {
        TessFrame::new(gpu, view, self.options.msaa)
    }

    /// The push constants of the drawing stages for `view`.
    pub fn params(&self, view: &View) -> TessParams {
        let (fixed, per_segment) = match self.options.levels {
            TessLevels::Fixed(l) => (l as f32, 1.0),
            TessLevels::Adaptive { pixels_per_segment } => (0.0, pixels_per_segment),
        };
        TessParams {
            world_to_clip: view.world_to_clip.to_cols_array_2d(),
            eye: view.eye.extend(1.0).to_array(),
            light: view.light.extend(0.0).to_array(),
            viewport: view.viewport().to_array(),
            pixels_per_segment: per_segment,
            fixed_level: fixed,
            min_level: self.options.min_level as f32,
            max_level: self.options.max_level as f32,
            render_capacity: self.options.patch_capacity,
            patches_per_instance: self.patches_per_instance,
        }
    }

    /// Records a whole frame (LOD, draw, downsample) into `frame`, for benchmarks. `frame`
    /// must have been made for `view` ([`ParamTess::frame`]).
    pub fn record(
        &self,
        rec: &Recorder,
        scene: &GpuParamScene,
        view: &View,
        frame: &TessFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        self.lod.record(rec, scene, view, None);
        self.record_draw(rec, scene, view, frame, pixels, background);
    }

    /// [`Self::record`] with the LOD stage and the drawing (draw and downsample) in timer
    /// scopes "lod" and "draw".
    #[allow(clippy::too_many_arguments)]
    pub fn record_timed(
        &self,
        rec: &Recorder,
        timer: &mut Timer,
        scene: &GpuParamScene,
        view: &View,
        frame: &TessFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        timer.scope(rec, "lod", |rec| self.lod.record(rec, scene, view, None));
        timer.scope(rec, "draw", |rec| {
            self.record_draw(rec, scene, view, frame, pixels, background)
        });
    }

    fn record_draw(
        &self,
        rec: &Recorder,
        scene: &GpuParamScene,
        view: &View,
        frame: &TessFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        let args = ArgsParams {
            render_capacity: self.options.patch_capacity,
            patches_per_instance: self.patches_per_instance,
        };
        rec.dispatch_groups(
            &self.args,
            &[
                Binding::Buffer(&self.lod.state),
                Binding::Buffer(&self.draw_args),
            ],
            bytemuck::bytes_of(&args),
            [1, 1, 1],
        );
        for image in [
            Some(&frame.colour),
            Some(&frame.depth),
            frame.msaa_colour.as_ref(),
        ]
        .into_iter()
        .flatten()
        {
            rec.discard_to_general(image);
        }
        rec.barrier();
        let clear = [background[0], background[1], background[2], 1.0];
        match &frame.msaa_colour {
            Some(ms) => rec.begin_rendering_resolved(ms, Some(&frame.depth), &frame.colour, clear),
            None => rec.begin_rendering_with_depth(&frame.colour, Some(&frame.depth), clear),
        }
        let [objects, values, table] = self.lod.scene_bindings(scene);
        rec.draw_indirect(
            &self.draw,
            &[
                objects,
                values,
                table,
                Binding::Buffer(&self.lod.render),
                Binding::Buffer(&self.lod.state),
            ],
            bytemuck::bytes_of(&self.params(view)),
            &self.draw_args,
            0,
        );
        rec.end_rendering();
        rec.barrier();
        let params = DownsampleParams {
            size: [view.size.0, view.size.1],
            supersample: view.supersample,
        };
        rec.dispatch(
            &self.downsample,
            &[
                Binding::StorageImage(&frame.colour),
                Binding::Buffer(&pixels.pixels),
            ],
            bytemuck::bytes_of(&params),
            [view.size.0, view.size.1, 1],
        );
        rec.barrier();
    }

    /// Renders `scene` from `camera` at `size` in front of `background`: the image and the GPU
    /// milliseconds of the frame. A frame that lost patches to full lists is an error.
    pub fn render_image(
        &self,
        gpu: &Gpu,
        scene: &GpuParamScene,
        camera: &OrbitCamera,
        size: (u32, u32),
        background: [f32; 3],
    ) -> Result<(RgbaImage, f64)> {
        let view = self.view(scene, camera, size)?;
        let frame = self.frame(gpu, &view)?;
        let pixels = Target::new(gpu, size.0, size.1)?;
        let info = self.render_frame(gpu, scene, &view, &frame, &pixels, background)?;
        Ok((pixels.read(gpu)?, info.gpu_ms))
    }

    /// Renders into `frame` and reports the frame's counters.
    pub fn render_frame(
        &self,
        gpu: &Gpu,
        scene: &GpuParamScene,
        view: &View,
        frame: &TessFrame,
        pixels: &Target,
        background: [f32; 3],
    ) -> Result<ParamFrameInfo> {
        let image = (pixels.width, pixels.height);
        let msaa = self.options.msaa;
        if frame.raster != view.raster_size() || image != view.size || frame.samples != msaa {
            return Err(Error::Invalid(format!(
                "param-tess: a frame of {image:?} pixels, raster {:?} and {} samples for a \
                 view of {:?}, raster {:?} and {msaa} samples",
                frame.raster,
                frame.samples,
                view.size,
                view.raster_size()
            )));
        }
        let gpu_ms = tessera_gpu::timing::time_once(gpu, "param-tess", |rec| {
            self.record(rec, scene, view, frame, pixels, background);
            Ok::<(), Error>(())
        })?;
        let stats = self.lod.read_frame_stats(gpu, "param-tess")?;
        Ok(ParamFrameInfo { gpu_ms, stats })
    }

    /// The last frame's indirect draw arguments: (vertices = patches per instance, instances,
    /// first vertex, first instance).
    pub fn read_draw_args(&self, gpu: &Gpu) -> Result<[u32; 4]> {
        let w = gpu.read_buffer_as::<u32>(&self.draw_args)?;
        Ok([w[0], w[1], w[2], w[3]])
    }

    /// Fills the patch lists and the draw arguments' instance count with all-ones words, so
    /// that tests catch what a frame never wrote (the vertex count stays 0: a draw of
    /// never-written arguments draws nothing rather than billions of patches).
    pub fn poison(&self, gpu: &Gpu) -> Result<()> {
        self.lod.poison(gpu)?;
        let words = [0u32, u32::MAX, u32::MAX, u32::MAX];
        gpu.write_buffer(&self.draw_args, bytemuck::cast_slice(&words))?;
        Ok(())
    }

    /// The patches to render of the last frame (in the GPU's arbitrary order).
    pub fn read_patches(&self, gpu: &Gpu) -> Result<Vec<GpuPatch>> {
        self.lod.read_patches(gpu)
    }
}
