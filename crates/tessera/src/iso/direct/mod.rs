//! Direct isosurface rasterization — paper D (Kreskowski et al.): task shaders find the
//! occupied cells of each 8×8×4 block, mesh shaders run marching cubes on lists of them and
//! hand the triangles straight to the rasterizer; nothing is stored.
//!
//! Differences from the paper: blocks the min-max grid rules out are dropped in the task
//! shader before any cell is read; the warp-level scans are shared-memory scans, so the
//! technique runs with any subgroup size; and a debug capture of the emitted triangles lets
//! tests hold the GPU to the CPU marching cubes exactly. Raster occlusion culling is in `cull`
//! (its occupied-region compaction is a compute pass, not a task shader), multiview stereo in
//! `stereo`, and the compute path for GPUs with few graphics units, with its own occlusion
//! culling, in `compute` and `compute_cull`.

pub mod block_list;
pub mod cell_boxes;
pub mod compute;
pub mod compute_cull;
mod compute_cull_frame;
pub mod cull;
pub mod cull_choice;
pub mod resolve;
pub mod stereo;

use crate::builtin_shader;
use crate::config::marching_cubes_defines;
use crate::error::{Error, Result};
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::PreparedVolume;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use cull::{CullPipelines, CullState, DrawBlockList};
use glam::Vec3;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::shading::BACKGROUND;
use tessera_data::{GridFrame, OrbitCamera, RgbaImage, ScalarType, View, Volume};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, Image, MemoryLocation, Pipeline, Recorder, RenderTargets,
    ShaderCompiler, Slot, Timer,
};

/// Cells one mesh workgroup handles at most: one per invocation of a 32-wide workgroup.
pub const MAX_CELLS_PER_LIST: u32 = 32;
/// Vertices one mesh workgroup emits at most: the paper's measured sweet spot.
pub const MAX_VERTICES_PER_LIST: u32 = 96;
/// Triangles one mesh workgroup emits at most. A cell's surface is closed loops through its
/// crossing edges, each triangulated into (length - 2) triangles, so a cell has at most
/// its vertex count minus two triangles (checked over every table row in
/// `tessera_data::mc_tables`); a list of at most 96 vertices and at least one cell thus has
/// at most 94 triangles, whatever the ambiguous faces decide.
pub const MAX_TRIANGLES_PER_LIST: u32 = MAX_VERTICES_PER_LIST - 2;

pub(crate) const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
pub(crate) const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Push constants shared by the three stages (`iso/direct/params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct DirectParams {
    pub grid_to_clip: [[f32; 4]; 4],
    pub eye_world: [f32; 3],
    pub isovalue: f32,
    pub grid_to_world: [f32; 4],
    pub light: [f32; 4],
    pub dims: [u32; 3],
    /// Triangles the mesh path's debug capture (0: off) or the compute path's list holds.
    pub triangle_capacity: u32,
}

impl DirectParams {
    /// The eye, light and world positions the compute path's resolve shades with.
    pub fn lighting(&self) -> resolve::Lighting {
        let (l, s) = (self.light, self.grid_to_world);
        resolve::Lighting {
            eye: self.eye_world,
            light: [l[0], l[1], l[2]],
            clip_to_world: resolve::clip_to_world(
                &self.grid_to_clip,
                [s[0], s[1], s[2]],
                self.dims,
            ),
        }
    }
}

/// What one frame did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DirectStats {
    pub mesh_workgroups: u32,
    pub triangles: u32,
    pub vertices: u32,
}

/// Colour and depth attachments plus a readback buffer.
pub struct RasterTarget {
    pub color: Image,
    pub depth: Image,
    readback: Buffer,
    pub width: u32,
    pub height: u32,
}

impl RasterTarget {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<RasterTarget> {
        Self::with_views(gpu, width, height, 1)
    }

    /// Attachments with one layer per view, for multiview rendering.
    pub fn with_views(gpu: &Gpu, width: u32, height: u32, views: u32) -> Result<RasterTarget> {
        crate::error::check_image_size(width, height)?;
        let color = gpu.create_image_layers(
            "direct colour",
            [width, height, 1],
            views,
            COLOR_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            false,
        )?;
        let depth = gpu.create_image_layers(
            "direct depth",
            [width, height, 1],
            views,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            false,
        )?;
        let readback = gpu.create_buffer(
            "direct colour readback",
            width as u64 * height as u64 * 4 * views.max(1) as u64,
            vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        Ok(RasterTarget {
            color,
            depth,
            readback,
            width,
            height,
        })
    }

    pub fn read(&self, gpu: &Gpu) -> Result<RgbaImage> {
        Ok(self.read_views(gpu)?.swap_remove(0))
    }

    /// Records a copy of the first view's colour into `target` (of this size), packed as the
    /// compute passes pack pixels.
    pub fn record_copy_to(&self, rec: &Recorder, target: &Target) {
        rec.copy_image_to_buffer(&self.color, &target.pixels);
    }

    /// Records a copy of view `layer`'s colour into `target` (of this size).
    pub fn record_layer_copy_to(&self, rec: &Recorder, layer: u32, target: &Target) {
        rec.copy_image_layer_to_buffer(&self.color, layer, &target.pixels);
    }

    /// One image per view (layer).
    pub fn read_views(&self, gpu: &Gpu) -> Result<Vec<RgbaImage>> {
        gpu.submit("copy direct colour", |rec| {
            rec.copy_image_to_buffer(&self.color, &self.readback)
        })?;
        let pixels: Vec<u32> = gpu.read_buffer_as(&self.readback)?;
        let per_view = (self.width * self.height) as usize;
        Ok(pixels
            .chunks_exact(per_view)
            .map(|p| RgbaImage {
                width: self.width,
                height: self.height,
                pixels: p.to_vec(),
            })
            .collect())
    }
}

/// Triangles captured from the mesh shaders, in grid coordinates.
pub type CapturedTriangle = [Vec3; 3];

pub struct Direct {
    /// Task workgroups over the whole block grid.
    pipeline: Pipeline,
    /// Task workgroups over a list of blocks (occlusion culling).
    list_pipeline: Pipeline,
    cull: CullPipelines,
    builder: MinMaxBuilder,
    stats: Buffer,
}

/// Draws block lists for the culling passes with the list pipeline.
struct ListDraw<'a> {
    direct: &'a Direct,
    prepared: &'a PreparedVolume,
    params: &'a DirectParams,
    capture: &'a Buffer,
    /// Where the task shader records each block's cell box.
    cell_boxes: &'a Buffer,
}

impl DrawBlockList for ListDraw<'_> {
    fn draw_blocks(&self, rec: &Recorder, list: &Buffer) -> Result<()> {
        let [volume, nodes, stats, capture, blocks] =
            self.direct.bindings(self.prepared, self.capture, list);
        rec.set_cull_mode(Direct::cull_mode(self.prepared, self.params));
        rec.draw_mesh_tasks_indirect(
            &self.direct.list_pipeline,
            &[
                volume,
                nodes,
                stats,
                capture,
                blocks,
                Binding::Buffer(self.cell_boxes),
            ],
            bytemuck::bytes_of(self.params),
            list,
            block_list::ARGS_OFFSET,
        )?;
        Ok(())
    }
}

impl Direct {
    /// The mesh path with ambiguous faces cut by the asymptotic decider.
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<Direct> {
        Self::with_rule(gpu, compiler, scalar, AmbiguityRule::default())
    }

    /// The mesh path with ambiguous faces cut by `rule`.
    pub fn with_rule(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
    ) -> Result<Direct> {
        if !gpu.caps().mesh_shader || !gpu.caps().task_shader {
            return Err(Error::Gpu(tessera_gpu::GpuError::Unsupported {
                device: gpu.caps().device_name.clone(),
                what: "task and mesh shaders (VK_EXT_mesh_shader)".into(),
            }));
        }
        let defines = marching_cubes_defines(scalar, rule);
        let with_list = |on: bool| {
            let mut d = defines.clone();
            d.push(("BLOCK_LIST".into(), u32::from(on).to_string()));
            d.extend(cell_boxes::cell_box_defines());
            d
        };
        let task = compiler.compile(&builtin_shader!("direct.task.glsl"), &with_list(false))?;
        let list_task = compiler.compile(&builtin_shader!("direct.task.glsl"), &with_list(true))?;
        let mut one_view = defines.clone();
        one_view.push(("MULTIVIEW".into(), "0".into()));
        let mesh = compiler.compile(&builtin_shader!("direct.mesh.glsl"), &one_view)?;
        let frag = compiler.compile(&builtin_shader!("direct.frag.glsl"), &one_view)?;
        let slots = [
            Slot::Texture,
            Slot::StorageBuffer,
            Slot::StorageBuffer,
            Slot::StorageBuffer,
            Slot::StorageBuffer,
        ];
        let targets = RenderTargets {
            dynamic_cull_mode: true,
            ..RenderTargets::color_depth(COLOR_FORMAT, DEPTH_FORMAT)
        };
        let pipeline = gpu.graphics_pipeline_for(
            "direct isosurface",
            &[&task, &mesh, &frag],
            &slots,
            &targets,
        )?;
        let list_slots = [&slots[..], &[Slot::StorageBuffer]].concat();
        let list_pipeline = gpu.graphics_pipeline_for(
            "direct isosurface (block list)",
            &[&list_task, &mesh, &frag],
            &list_slots,
            &targets,
        )?;
        let stats = crate::raster::create_counts_buffer(gpu, "direct stats")?;
        Ok(Direct {
            pipeline,
            list_pipeline,
            cull: CullPipelines::new(gpu, compiler)?,
            builder: MinMaxBuilder::new(gpu, compiler, scalar)?,
            stats,
        })
    }

    pub fn prepare(&self, gpu: &Gpu, volume: &Volume) -> Result<PreparedVolume> {
        PreparedVolume::new(gpu, &self.builder, volume)
    }

    pub fn params(
        prepared: &PreparedVolume,
        iso: f32,
        camera: &OrbitCamera,
        width: u32,
        height: u32,
        capture_capacity: u32,
    ) -> DirectParams {
        let view = View::of_unit_box(camera, (width, height));
        Self::params_for_view(prepared, iso, &view, capture_capacity)
    }

    pub fn params_for_view(
        prepared: &PreparedVolume,
        iso: f32,
        view: &View,
        capture_capacity: u32,
    ) -> DirectParams {
        let dims = prepared.volume.dims;
        let frame = GridFrame::new(dims, prepared.spacing);
        let e = view.eye;
        DirectParams {
            grid_to_clip: view.grid_to_clip(&frame).to_cols_array_2d(),
            eye_world: e.to_array(),
            isovalue: iso,
            grid_to_world: frame.grid_to_world.extend(0.0).to_array(),
            light: view.light.extend(0.0).to_array(),
            dims,
            triangle_capacity: capture_capacity,
        }
    }

    /// The screen winding of the triangles no pixel of the frame `params` describes can show:
    /// `Some` when the surface is closed (no boundary sample on the far side of the isovalue)
    /// and the whole grid lies before the near plane ([`tessera_data::facing`]), unless the
    /// volume's [`PreparedVolume::hidden_side`] says to draw it; the compute path's raster
    /// passes then leave them out.
    pub fn hidden_winding(
        prepared: &PreparedVolume,
        params: &DirectParams,
    ) -> Option<tessera_data::rasterize::ScreenWinding> {
        let side = prepared.closed_side(params.isovalue)?;
        tessera_data::facing::hidden_winding(
            glam::Mat4::from_cols_array_2d(&params.grid_to_clip),
            params.dims,
            side,
        )
    }

    /// The faces the mesh path's draws cull: those of [`Self::hidden_winding`]. Vulkan takes a
    /// triangle for front-facing (counter-clockwise) when -1/2 Σ (x_i y_i+1 - x_i+1 y_i) over its
    /// framebuffer corners is positive, the opposite sign of
    /// [`tessera_data::rasterize::ScreenWinding`]'s area on the same grid (x right, y down).
    pub fn cull_mode(prepared: &PreparedVolume, params: &DirectParams) -> vk::CullModeFlags {
        Self::cull_mode_of(Self::hidden_winding(prepared, params))
    }

    /// The winding both eyes of a pair hide, where they agree (one cull mode serves both
    /// views of a multiview pass); `None` when either eye must draw both sides.
    pub fn pair_hidden_winding(
        prepared: &PreparedVolume,
        eyes: &[DirectParams; 2],
    ) -> Option<tessera_data::rasterize::ScreenWinding> {
        let [first, second] = eyes.map(|eye| Self::hidden_winding(prepared, &eye));
        first.filter(|_| first == second)
    }

    /// The faces Vulkan culls to leave out triangles of `hidden` winding (see [`Self::cull_mode`]).
    pub(crate) fn cull_mode_of(
        hidden: Option<tessera_data::rasterize::ScreenWinding>,
    ) -> vk::CullModeFlags {
        use tessera_data::rasterize::ScreenWinding;
        match hidden {
            None => vk::CullModeFlags::NONE,
            Some(ScreenWinding::Positive) => vk::CullModeFlags::BACK,
            Some(ScreenWinding::Negative) => vk::CullModeFlags::FRONT,
        }
    }

    pub(crate) fn bindings<'a>(
        &'a self,
        prepared: &'a PreparedVolume,
        capture: &'a Buffer,
        list: &'a Buffer,
    ) -> [Binding<'a>; 5] {
        [
            Binding::Texture {
                image: &prepared.volume.texture,
                linear: false,
            },
            Binding::Buffer(&prepared.octree.nodes),
            Binding::Buffer(&self.stats),
            Binding::Buffer(capture),
            Binding::Buffer(list),
        ]
    }

    pub(crate) fn record_stats_reset(&self, rec: &Recorder) {
        rec.fill_buffer(&self.stats, 0);
        rec.barrier();
    }

    /// Records one frame into `target`, with occlusion culling when `culling` is given.
    /// `capture` must be bound whenever `params.triangle_capacity` is non-zero.
    pub fn record(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        target: &RasterTarget,
        params: &DirectParams,
        capture: &Buffer,
        culling: Option<&CullState>,
    ) -> Result<()> {
        rec.fill_buffer(&self.stats, 0);
        rec.barrier();
        rec.discard_to_general(&target.color);
        rec.discard_to_general(&target.depth);
        if let Some(state) = culling {
            let draw = ListDraw {
                direct: self,
                prepared,
                params,
                capture,
                cell_boxes: &state.cell_boxes.buffer,
            };
            return self.cull.record_frame(
                rec,
                state,
                prepared,
                params,
                &target.color,
                &target.depth,
                BACKGROUND,
                &draw,
            );
        }
        rec.begin_rendering_with_depth(&target.color, Some(&target.depth), BACKGROUND);
        rec.set_cull_mode(Self::cull_mode(prepared, params));
        // The whole grid is drawn; the list binding is unused, any buffer will do.
        let bindings = self.bindings(prepared, capture, &self.stats);
        let drawn = rec.draw_mesh_tasks(
            &self.pipeline,
            &bindings,
            bytemuck::bytes_of(params),
            prepared.octree.level_dims[0],
        );
        rec.end_rendering();
        rec.barrier();
        Ok(drawn?)
    }

    /// Renders one frame; returns the image, what the mesh shaders emitted and the GPU time
    /// in milliseconds. With `capture_capacity > 0`, also the emitted triangles.
    pub fn render(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        target: &RasterTarget,
        iso: f32,
        camera: &OrbitCamera,
        options: &FrameOptions,
    ) -> Result<DirectFrame> {
        let (capture_capacity, culling) = (options.capture_capacity, options.culling);
        let params = Self::params(
            prepared,
            iso,
            camera,
            target.width,
            target.height,
            capture_capacity,
        );
        let capture = gpu.create_buffer(
            "direct triangle capture",
            4 + capture_capacity as u64 * 36,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let mut timer = Timer::new(gpu, 1)?;
        timer.reset(gpu);
        let mut recorded = Ok(());
        let submitted = gpu.submit("direct isosurface", |rec| {
            rec.fill_buffer(&capture, 0);
            rec.barrier();
            recorded = timer.scope(rec, "direct", |rec| {
                self.record(rec, prepared, target, &params, &capture, culling)
            });
        });
        submitted
            .map_err(Error::from)
            .and(recorded)
            .and_then(|_| self.collect(gpu, target, &timer, &capture, capture_capacity))
    }

    /// What the last recorded frame emitted.
    pub fn read_stats(&self, gpu: &Gpu) -> Result<DirectStats> {
        let s: Vec<u32> = gpu.read_buffer_as(&self.stats)?;
        Ok(DirectStats {
            mesh_workgroups: s[0],
            triangles: s[1],
            vertices: s[2],
        })
    }

    /// A capture buffer for frames that capture nothing (the binding must still be valid).
    pub fn no_capture(gpu: &Gpu) -> Result<Buffer> {
        Ok(gpu.create_buffer(
            "direct no capture",
            16,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?)
    }

    fn collect(
        &self,
        gpu: &Gpu,
        target: &RasterTarget,
        timer: &Timer,
        capture: &Buffer,
        capacity: u32,
    ) -> Result<DirectFrame> {
        let ms = timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0);
        let stats = self.read_stats(gpu)?;
        let triangles = if capacity > 0 {
            let words: Vec<u32> = gpu.read_buffer_as(capture)?;
            let count = words[0];
            if count > capacity {
                return Err(Error::Invalid(format!(
                    "{count} triangles emitted, capture holds {capacity}"
                )));
            }
            let xyz: &[f32] = bytemuck::cast_slice(&words[1..]);
            Some(
                (0..count as usize)
                    .map(|t| {
                        let v = |j: usize| Vec3::from_slice(&xyz[t * 9 + 3 * j..t * 9 + 3 * j + 3]);
                        [v(0), v(1), v(2)]
                    })
                    .collect(),
            )
        } else {
            None
        };
        Ok(DirectFrame {
            image: target.read(gpu)?,
            stats,
            gpu_ms: ms,
            triangles,
        })
    }
}

/// Extras of one [`Direct::render`] call.
#[derive(Default, Clone, Copy)]
pub struct FrameOptions<'a> {
    /// Capture up to this many emitted triangles (0: no capture).
    pub capture_capacity: u32,
    /// Occlusion culling with this state (carried from frame to frame).
    pub culling: Option<&'a CullState>,
}

/// One rendered frame of [`Direct::render`].
pub struct DirectFrame {
    pub image: RgbaImage,
    pub stats: DirectStats,
    pub gpu_ms: f64,
    pub triangles: Option<Vec<CapturedTriangle>>,
}
