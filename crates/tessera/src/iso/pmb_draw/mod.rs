//! Drawing a PMB extraction ([`GpuPmb`]) from any view without extracting again, each block
//! first tested against the view frustum by the box of its cells. The draws share the meshlet
//! draw's push constants ([`MeshletDrawParams`]), fragment shading, triangle-list format and
//! resolve, so every stored surface shades as `direct` does.
//!
//! Both paths start from the number of blocks the extraction wrote, copied on the GPU into
//! indirect dispatch arguments ([`IndirectArgs`]), so an extraction recorded just before is
//! drawn without a readback.
//!
//! * Graphics path: a compute pass turns each surviving block descriptor into one
//!   `VkDrawIndexedIndirectCommand` (its 16-bit block-local indices, offset by its first
//!   vertex), packed and counted (`commands.comp.glsl`); one indexed indirect draw with that
//!   count runs a vertex shader that reads the positions and normals (`draw.vert.glsl`) and
//!   the meshlet draw's fragment shader.
//! * Compute path: one workgroup per block writes its triangles with their shading attributes
//!   into the frame's list (`triangles.comp.glsl`), which the shared compute rasterizer draws
//!   and `direct`'s resolve shades ([`ListResolve`]).

use crate::builtin_shader;
use crate::config::pmb_draw_defines;
use crate::error::{Error, Result};
use crate::iso::direct::compute::ComputeTarget;
use crate::iso::direct::{RasterTarget, COLOR_FORMAT, DEPTH_FORMAT};
use crate::iso::meshlet_draw::list::ListResolve;
use crate::iso::meshlet_draw::MeshletDrawParams;
use crate::iso::pmb::{GpuPmb, PmbBlockSize};
use crate::path::{Path, Support};
use crate::raster::{create_counts_buffer, IndirectArgs};
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_data::shading::BACKGROUND;
use tessera_gpu::{
    vk, Binding, Buffer, Capabilities, Gpu, IndexedDraws, MemoryLocation, Pipeline, Readback,
    Recorder, RenderTargets, ShaderCompiler, Slot, INDEXED_COMMAND_BYTES,
};

/// Blocks one workgroup of the command pass turns into draws (`PMB_DRAW_GROUP`).
pub const COMMAND_GROUP: u32 = 64;

/// Where the block count sits in the indirect-arguments buffer; the dispatch follows it.
const DISPATCH_OFFSET: u64 = 4;

/// Bytes of [`PmbDrawCounters`].
const COUNTER_BYTES: u64 = std::mem::size_of::<PmbDrawCounters>() as u64;

/// What the last frame drew (`PmbDrawCounters` in `blocks.glsl`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
#[repr(C)]
pub struct PmbDrawCounters {
    /// Blocks that passed culling (on the graphics path, the indexed draws made).
    pub blocks_drawn: u32,
    /// Their triangles.
    pub triangles_drawn: u32,
}

/// One indexed draw as the command pass writes it: Vulkan's `VkDrawIndexedIndirectCommand`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
#[repr(C)]
pub struct DrawIndexedIndirectCommand {
    pub index_count: u32,
    pub instance_count: u32,
    pub first_index: u32,
    pub vertex_offset: i32,
    pub first_instance: u32,
}

const _: () = assert!(std::mem::size_of::<DrawIndexedIndirectCommand>() == 20);
const _: () = assert!(INDEXED_COMMAND_BYTES == 20);

/// What each path of the PMB draw needs of a device: the graphics path indexed draws counted
/// on the GPU, the compute path the compute rasterizer's 64-bit atomics.
pub fn path_support(caps: &Capabilities) -> Support {
    Support {
        graphics: caps.draw_indirect_count,
        graphics_needs: "indirect draw counts (drawIndirectCount, multiDrawIndirect)",
        compute: caps.buffer_int64_atomics,
        compute_needs: "64-bit buffer atomics",
    }
}

enum Passes {
    Graphics(Box<GraphicsPasses>),
    Compute(Box<ComputePasses>),
}

struct GraphicsPasses {
    commands: Pipeline,
    draw: Pipeline,
    /// One command per block of the volume ([`PmbDraw::prepare`]).
    command_buffer: Option<Buffer>,
    command_capacity: u32,
}

struct ComputePasses {
    triangles: Pipeline,
    list: ListResolve,
}

/// The draw pipelines of one path for one block size.
pub struct PmbDraw {
    passes: Passes,
    indirect: IndirectArgs,
    /// The block count, then the dispatch over the blocks.
    block_count: Buffer,
    counters: Buffer,
    /// `counters` copied to the host at the end of each frame.
    readback: Readback,
    block_size: PmbBlockSize,
}

/// The slots every pass binds first (`blocks.glsl`).
const BLOCK_SLOTS: usize = 3;

impl PmbDraw {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        path: Path,
        block_size: PmbBlockSize,
    ) -> Result<PmbDraw> {
        let defines = pmb_draw_defines(block_size);
        let support = path_support(gpu.caps());
        let supported = match path {
            Path::Graphics => support.graphics,
            Path::Compute => support.compute,
        };
        if !supported {
            let what = match path {
                Path::Graphics => support.graphics_needs,
                Path::Compute => support.compute_needs,
            };
            return Err(Error::Gpu(tessera_gpu::GpuError::Unsupported {
                device: gpu.caps().device_name.clone(),
                what: what.into(),
            }));
        }
        let passes = match path {
            Path::Graphics => {
                let commands =
                    compiler.compile(&builtin_shader!("commands.comp.glsl"), &defines)?;
                let vert = compiler.compile(&builtin_shader!("draw.vert.glsl"), &defines)?;
                let frag = compiler
                    .compile(&builtin_shader!("../meshlet_draw/draw.frag.glsl"), &defines)?;
                Passes::Graphics(Box::new(GraphicsPasses {
                    commands: gpu.compute_pipeline(
                        "PMB draw commands",
                        &commands,
                        &[Slot::StorageBuffer; BLOCK_SLOTS + 1],
                    )?,
                    draw: gpu.graphics_pipeline_for(
                        "PMB draw",
                        &[&vert, &frag],
                        &[Slot::StorageBuffer; 2],
                        &RenderTargets::color_depth(COLOR_FORMAT, DEPTH_FORMAT),
                    )?,
                    command_buffer: None,
                    command_capacity: 0,
                }))
            }
            Path::Compute => {
                let triangles =
                    compiler.compile(&builtin_shader!("triangles.comp.glsl"), &defines)?;
                Passes::Compute(Box::new(ComputePasses {
                    triangles: gpu.compute_pipeline(
                        "PMB triangles",
                        &triangles,
                        &[Slot::StorageBuffer; BLOCK_SLOTS + 6],
                    )?,
                    list: ListResolve::new(gpu, compiler, "PMB")?,
                }))
            }
        };
        let counters = gpu.create_buffer(
            "PMB draw counters",
            std::mem::size_of::<PmbDrawCounters>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::INDIRECT_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(PmbDraw {
            passes,
            indirect: IndirectArgs::new(gpu, compiler)?,
            block_count: create_counts_buffer(gpu, "PMB draw block count")?,
            counters,
            readback: gpu.create_readback("PMB draw counters (host)", COUNTER_BYTES)?,
            block_size,
        })
    }

    pub fn path(&self) -> Path {
        match self.passes {
            Passes::Graphics(_) => Path::Graphics,
            Passes::Compute(_) => Path::Compute,
        }
    }

    /// Makes what drawing `pmb` needs beyond the pipelines (the graphics path's command
    /// buffer, one command per block of the volume); nothing when it exists.
    pub fn prepare(&mut self, gpu: &Gpu, pmb: &GpuPmb) -> Result<()> {
        self.check(pmb)?;
        let Passes::Graphics(passes) = &mut self.passes else {
            return Ok(());
        };
        if passes.command_buffer.is_none() || passes.command_capacity < pmb.block_capacity {
            passes.command_buffer = None;
            passes.command_buffer = Some(gpu.create_buffer(
                "PMB draw commands",
                u64::from(pmb.block_capacity) * u64::from(INDEXED_COMMAND_BYTES),
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )?);
            passes.command_capacity = pmb.block_capacity;
        }
        Ok(())
    }

    fn check(&self, pmb: &GpuPmb) -> Result<()> {
        if pmb.block_size != self.block_size.cells() {
            return Err(Error::Invalid(format!(
                "PMB draw: built for {} blocks, the mesh has {:?}",
                self.block_size.name(),
                pmb.block_size
            )));
        }
        Ok(())
    }

    /// Resets the counters and turns `pmb`'s block count into a dispatch of `group_size`
    /// blocks per workgroup.
    fn record_block_count(&self, rec: &Recorder, pmb: &GpuPmb, group_size: u32) {
        rec.fill_buffer(&self.counters, 0);
        rec.copy_buffer(&pmb.counters, &self.block_count, 4);
        rec.barrier();
        self.indirect.record(rec, &self.block_count, group_size);
    }

    fn block_bindings<'a>(&'a self, pmb: &'a GpuPmb) -> [Binding<'a>; BLOCK_SLOTS] {
        [
            Binding::Buffer(&self.block_count),
            Binding::Buffer(&pmb.descriptors),
            Binding::Buffer(&self.counters),
        ]
    }

    /// Records the graphics path's draw of `pmb` into `target` (after [`Self::prepare`]).
    /// The block count is read on the GPU from `pmb`'s counters, so an extraction recorded
    /// just before (and separated by a barrier) is drawn without a readback.
    pub fn record_graphics(
        &self,
        rec: &Recorder,
        pmb: &GpuPmb,
        target: &RasterTarget,
        params: &MeshletDrawParams,
    ) -> Result<()> {
        let Passes::Graphics(passes) = &self.passes else {
            return Err(Error::Invalid(
                "PMB draw: built for the compute path".into(),
            ));
        };
        self.check(pmb)?;
        let commands = match &passes.command_buffer {
            Some(buffer) if passes.command_capacity >= pmb.block_capacity => buffer,
            _ => {
                return Err(Error::Invalid(
                    "PMB draw: recorded before prepare for this mesh".into(),
                ))
            }
        };
        let push = bytemuck::bytes_of(params);
        self.record_block_count(rec, pmb, COMMAND_GROUP);
        let [counts, descriptors, counters] = self.block_bindings(pmb);
        rec.dispatch_indirect(
            &passes.commands,
            &[counts, descriptors, counters, Binding::Buffer(commands)],
            push,
            &self.block_count,
            DISPATCH_OFFSET,
        );
        rec.barrier();
        rec.discard_to_general(&target.color);
        rec.discard_to_general(&target.depth);
        rec.begin_rendering_with_depth(&target.color, Some(&target.depth), BACKGROUND);
        let drawn = rec.draw_indexed_indirect_count(
            &passes.draw,
            &[
                Binding::Buffer(&pmb.positions),
                Binding::Buffer(&pmb.normals),
            ],
            push,
            &IndexedDraws {
                indices: &pmb.indices,
                commands,
                commands_offset: 0,
                count: &self.counters,
                count_offset: 0,
                max_draws: pmb.block_capacity,
            },
        );
        rec.end_rendering();
        rec.barrier();
        self.readback
            .record_copy(rec, &self.counters, 0, COUNTER_BYTES);
        Ok(drawn?)
    }

    /// Records the compute path's draw of `pmb` through `target`'s list and frame, shaded
    /// into `pixels`; `params.triangle_capacity` must be the list's capacity. As on the
    /// graphics path, the block count is read on the GPU.
    pub fn record_compute(
        &self,
        rec: &Recorder,
        pmb: &GpuPmb,
        target: &ComputeTarget,
        pixels: &Target,
        params: &MeshletDrawParams,
    ) -> Result<()> {
        let Passes::Compute(passes) = &self.passes else {
            return Err(Error::Invalid(
                "PMB draw: built for the graphics path".into(),
            ));
        };
        self.check(pmb)?;
        ListResolve::check_sizes("PMB draw", target, pixels)?;
        rec.fill_buffer(&target.lists.counts, 0);
        target.frame.record_begin(rec);
        self.record_block_count(rec, pmb, 1);
        let bindings: Vec<Binding> = self
            .block_bindings(pmb)
            .into_iter()
            .chain([
                Binding::Buffer(&pmb.positions),
                Binding::Buffer(&pmb.normals),
                Binding::Buffer(&pmb.indices),
                Binding::Buffer(&target.lists.triangles),
                Binding::Buffer(&target.lists.attributes),
                Binding::Buffer(&target.lists.counts),
            ])
            .collect();
        rec.dispatch_indirect(
            &passes.triangles,
            &bindings,
            bytemuck::bytes_of(params),
            &self.block_count,
            DISPATCH_OFFSET,
        );
        rec.barrier();
        passes.list.record(rec, target, pixels, params);
        self.readback
            .record_copy(rec, &self.counters, 0, COUNTER_BYTES);
        Ok(())
    }

    /// What the last recorded frame drew (read after it was submitted): copied to the host
    /// at the frame's end, so reading takes no submission.
    pub fn read_counters(&self) -> PmbDrawCounters {
        self.readback
            .bytes()
            .get(..COUNTER_BYTES as usize)
            .map(bytemuck::pod_read_unaligned)
            .unwrap_or_default()
    }

    /// The graphics path's draw commands of the last frame (for tests); empty on the compute
    /// path.
    pub fn read_commands(&self, gpu: &Gpu) -> Result<Vec<DrawIndexedIndirectCommand>> {
        let Passes::Graphics(passes) = &self.passes else {
            return Ok(Vec::new());
        };
        let Some(buffer) = &passes.command_buffer else {
            return Ok(Vec::new());
        };
        let drawn = self.read_counters().blocks_drawn as usize;
        let commands: Vec<DrawIndexedIndirectCommand> = gpu.read_buffer_as(buffer)?;
        Ok(commands.into_iter().take(drawn).collect())
    }
}
