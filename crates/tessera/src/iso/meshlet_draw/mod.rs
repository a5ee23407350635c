//! Drawing persistent meshlets (paper C §3.3): an extraction's [`GpuMeshlets`] (or meshlets
//! uploaded from the CPU, the offline reference's) drawn from any view without extracting
//! again, each meshlet first tested against the view frustum by its box.
//!
//! * Graphics path, the paper's: a task workgroup tests 32 meshlets and launches one mesh
//!   workgroup per survivor, which projects its vertices and emits its triangles from the
//!   8-bit local indices; a fragment shader shades them (`draw.*.glsl`).
//! * Compute path: one workgroup per meshlet tests it and writes its triangles with their
//!   shading attributes into the frame's list (`triangles.comp.glsl`), which the shared
//!   compute rasterizer draws and `direct`'s resolve shades, so the two paths and `direct`
//!   shade alike.
//!
//! The box is the explicit AABB of the meshlet's vertices, or the implicit one of the
//! subblock it was extracted from (no bounds stored; the paper's cheaper choice); frustum
//! culling only drops meshlets wholly beyond one clip plane, so it never changes the image.
//! The compute path can also cull occluded meshlets against a max-depth pyramid of what the
//! meshlets visible last frame drew ([`occlusion`]).

mod occlusion;

pub use occlusion::{MeshletOcclusion, OcclusionCounters};

pub mod list;

use crate::builtin_shader;
use crate::config::meshlet_draw_defines;
use crate::error::{Error, Result};
use crate::iso::direct::compute::ComputeTarget;
use crate::iso::direct::{RasterTarget, COLOR_FORMAT, DEPTH_FORMAT};
use crate::iso::meshlets::GpuMeshlets;
use crate::path::Path;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use list::ListResolve;
use tessera_data::shading::BACKGROUND;
use tessera_data::{GridFrame, View};
use tessera_gpu::{
    spread_groups, vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Readback, Recorder,
    RenderTargets, ShaderCompiler, Slot,
};

/// Meshlets one task workgroup tests (one invocation each).
pub const TASK_SIZE: u32 = 32;

/// The box a meshlet is frustum-culled by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshletBounds {
    /// The AABB of its vertices, stored with it.
    #[default]
    Explicit,
    /// The cells of the subblock it came from (the explicit box for meshlets without one).
    Implicit,
    /// No culling.
    None,
}

impl MeshletBounds {
    pub const ALL: [MeshletBounds; 3] = [
        MeshletBounds::Explicit,
        MeshletBounds::Implicit,
        MeshletBounds::None,
    ];

    /// The value `params.bounds` carries (`MESHLET_BOUNDS_*`).
    pub fn code(self) -> u32 {
        match self {
            MeshletBounds::Explicit => 0,
            MeshletBounds::Implicit => 1,
            MeshletBounds::None => 2,
        }
    }
}

/// Push constants of every draw pass (`params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MeshletDrawParams {
    pub grid_to_clip: [[f32; 4]; 4],
    pub eye_world: [f32; 3],
    /// [`MeshletBounds::code`].
    pub bounds: u32,
    pub grid_to_world: [f32; 3],
    /// Compute path: the frame's size in pixels (occlusion culling reads its pyramid).
    pub frame_width: u32,
    pub light: [f32; 3],
    pub frame_height: u32,
    pub dims: [u32; 3],
    /// Compute path: triangles the frame's list holds.
    pub triangle_capacity: u32,
}

impl MeshletDrawParams {
    /// The draw of meshlets of a volume of `dims` samples and `spacing` seen in `view`.
    pub fn new(
        view: &View,
        dims: [u32; 3],
        spacing: [f32; 3],
        bounds: MeshletBounds,
        triangle_capacity: u32,
    ) -> MeshletDrawParams {
        let frame = GridFrame::new(dims, spacing);
        MeshletDrawParams {
            grid_to_clip: view.grid_to_clip(&frame).to_cols_array_2d(),
            eye_world: view.eye.to_array(),
            bounds: bounds.code(),
            grid_to_world: frame.grid_to_world.to_array(),
            frame_width: view.size.0,
            light: view.light.to_array(),
            frame_height: view.size.1,
            dims,
            triangle_capacity,
        }
    }
}

/// Bytes of [`DrawCounters`].
const COUNTER_BYTES: u64 = std::mem::size_of::<DrawCounters>() as u64;

/// What the last frame drew.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
#[repr(C)]
pub struct DrawCounters {
    /// Meshlets that passed culling.
    pub meshlets_drawn: u32,
    /// Their triangles.
    pub triangles_drawn: u32,
}

enum Passes {
    Graphics(Pipeline),
    Compute(Box<ComputePasses>),
}

struct ComputePasses {
    triangles: Pipeline,
    list: ListResolve,
    occlusion: Option<occlusion::OcclusionPasses>,
}

/// The draw pipelines of one path.
pub struct MeshletDraw {
    passes: Passes,
    counters: Buffer,
    readback: Readback,
    max_groups_x: u32,
}

const READ_SLOTS: usize = 6;

impl MeshletDraw {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, path: Path) -> Result<MeshletDraw> {
        Self::build(gpu, compiler, path, false)
    }

    /// The compute path with occlusion culling ([`MeshletDraw::record_compute_culled`]).
    pub fn with_occlusion(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<MeshletDraw> {
        Self::build(gpu, compiler, Path::Compute, true)
    }

    fn build(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        path: Path,
        occlusion: bool,
    ) -> Result<MeshletDraw> {
        let defines = meshlet_draw_defines();
        let passes = match path {
            Path::Graphics => {
                if !(gpu.caps().mesh_shader && gpu.caps().task_shader) {
                    return Err(Error::Gpu(tessera_gpu::GpuError::Unsupported {
                        device: gpu.caps().device_name.clone(),
                        what: "task and mesh shaders (VK_EXT_mesh_shader)".into(),
                    }));
                }
                let task = compiler.compile(&builtin_shader!("draw.task.glsl"), &defines)?;
                let mesh = compiler.compile(&builtin_shader!("draw.mesh.glsl"), &defines)?;
                let frag = compiler.compile(&builtin_shader!("draw.frag.glsl"), &defines)?;
                Passes::Graphics(gpu.graphics_pipeline_for(
                    "meshlet draw",
                    &[&task, &mesh, &frag],
                    &[Slot::StorageBuffer; READ_SLOTS],
                    &RenderTargets::color_depth(COLOR_FORMAT, DEPTH_FORMAT),
                )?)
            }
            Path::Compute => {
                let triangles =
                    compiler.compile(&builtin_shader!("triangles.comp.glsl"), &defines)?;
                Passes::Compute(Box::new(ComputePasses {
                    triangles: gpu.compute_pipeline(
                        "meshlet triangles",
                        &triangles,
                        &[Slot::StorageBuffer; READ_SLOTS + 3],
                    )?,
                    list: ListResolve::new(gpu, compiler, "meshlet")?,
                    occlusion: if occlusion {
                        Some(occlusion::OcclusionPasses::new(gpu, compiler)?)
                    } else {
                        None
                    },
                }))
            }
        };
        let counters = gpu.create_buffer(
            "meshlet draw counters",
            std::mem::size_of::<DrawCounters>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(MeshletDraw {
            passes,
            counters,
            // This draw's counters, then (occlusion culling) pass 2's.
            readback: gpu.create_readback("meshlet draw counters (host)", 2 * COUNTER_BYTES)?,
            max_groups_x: gpu.caps().max_compute_workgroup_count[0],
        })
    }

    pub fn path(&self) -> Path {
        match self.passes {
            Passes::Graphics(_) => Path::Graphics,
            Passes::Compute(_) => Path::Compute,
        }
    }

    fn read_bindings<'a>(&'a self, meshlets: &'a GpuMeshlets) -> [Binding<'a>; READ_SLOTS] {
        [
            Binding::Buffer(&meshlets.counters),
            Binding::Buffer(&meshlets.meshlets),
            Binding::Buffer(&meshlets.positions),
            Binding::Buffer(&meshlets.normals),
            Binding::Buffer(&meshlets.local_indices),
            Binding::Buffer(&self.counters),
        ]
    }

    /// Records the graphics path's draw of `meshlets` into `target`. The meshlet count is
    /// read on the GPU from their counters, so an extraction recorded just before (and
    /// separated by a barrier) is drawn without a readback; workgroups are launched for the
    /// buffers' capacity.
    pub fn record_graphics(
        &self,
        rec: &Recorder,
        meshlets: &GpuMeshlets,
        target: &RasterTarget,
        params: &MeshletDrawParams,
    ) -> Result<()> {
        let Passes::Graphics(pipeline) = &self.passes else {
            return Err(Error::Invalid(
                "meshlet draw: built for the compute path".into(),
            ));
        };
        rec.fill_buffer(&self.counters, 0);
        rec.barrier();
        rec.discard_to_general(&target.color);
        rec.discard_to_general(&target.depth);
        rec.begin_rendering_with_depth(&target.color, Some(&target.depth), BACKGROUND);
        let groups = meshlets.capacity.meshlets.div_ceil(TASK_SIZE);
        let drawn = rec.draw_mesh_tasks(
            pipeline,
            &self.read_bindings(meshlets),
            bytemuck::bytes_of(params),
            spread_groups(groups, self.max_groups_x),
        );
        rec.end_rendering();
        rec.barrier();
        self.readback
            .record_copy(rec, &self.counters, 0, COUNTER_BYTES);
        Ok(drawn?)
    }

    /// Records the compute path's draw of `meshlets` through `target`'s list and frame,
    /// shaded into `pixels`; `params.triangle_capacity` must be the list's capacity. As on
    /// the graphics path, the count is read on the GPU.
    pub fn record_compute(
        &self,
        rec: &Recorder,
        meshlets: &GpuMeshlets,
        target: &ComputeTarget,
        pixels: &Target,
        params: &MeshletDrawParams,
    ) -> Result<()> {
        let passes = self.compute_passes()?;
        ListResolve::check_sizes("meshlet draw", target, pixels)?;
        let ComputePasses {
            triangles, list, ..
        } = passes;
        rec.fill_buffer(&self.counters, 0);
        rec.fill_buffer(&target.lists.counts, 0);
        target.frame.record_begin(rec);
        rec.barrier();
        let read = self.read_bindings(meshlets);
        let bindings: Vec<Binding> = read
            .into_iter()
            .chain([
                Binding::Buffer(&target.lists.triangles),
                Binding::Buffer(&target.lists.attributes),
                Binding::Buffer(&target.lists.counts),
            ])
            .collect();
        rec.dispatch_groups(
            triangles,
            &bindings,
            bytemuck::bytes_of(params),
            spread_groups(meshlets.capacity.meshlets, self.max_groups_x),
        );
        rec.barrier();
        list.record(rec, target, pixels, params);
        self.readback
            .record_copy(rec, &self.counters, 0, COUNTER_BYTES);
        Ok(())
    }

    fn compute_passes(&self) -> Result<&ComputePasses> {
        match &self.passes {
            Passes::Compute(passes) => Ok(passes),
            Passes::Graphics(_) => Err(Error::Invalid(
                "meshlet draw: built for the graphics path".into(),
            )),
        }
    }

    /// What the last recorded frame drew (read after it was submitted): copied to the host
    /// at the frame's end, so reading takes no submission.
    pub fn read_counters(&self) -> DrawCounters {
        self.counters_at(0)
    }

    fn counters_at(&self, offset: u64) -> DrawCounters {
        let at = offset as usize;
        self.readback
            .bytes()
            .get(at..at + COUNTER_BYTES as usize)
            .map(bytemuck::pod_read_unaligned)
            .unwrap_or_default()
    }
}
