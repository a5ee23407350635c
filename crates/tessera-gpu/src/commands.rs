//! Command recording and one-shot submission.

use crate::accel::AccelerationStructure;
use crate::context::Gpu;
use crate::error::{GpuError, Result};
use crate::memory::{Buffer, Image};
use crate::pipeline::{Pipeline, Slot, PUSH_CONSTANT_BYTES};
use crate::timer::Timer;
use ash::vk;

/// A resource bound to the slot of the same index.
#[derive(Clone, Copy)]
pub enum Binding<'a> {
    Buffer(&'a Buffer),
    /// Sampled through the device's clamp-to-edge sampler; `linear` picks the filter.
    Texture {
        image: &'a Image,
        linear: bool,
    },
    StorageImage(&'a Image),
    /// A top-level acceleration structure for `traceRayEXT`.
    AccelerationStructure(&'a AccelerationStructure),
}

/// Bytes of one `VkDrawIndexedIndirectCommand`, the stride of packed commands.
pub const INDEXED_COMMAND_BYTES: u32 = 20;

/// The buffers of [`Recorder::draw_indexed_indirect_count`].
#[derive(Clone, Copy)]
pub struct IndexedDraws<'a> {
    /// 16-bit indices (made with `INDEX_BUFFER` usage).
    pub indices: &'a Buffer,
    /// Packed draw commands (made with `INDIRECT_BUFFER` usage).
    pub commands: &'a Buffer,
    pub commands_offset: u64,
    /// Holds the number of draws (made with `INDIRECT_BUFFER` usage).
    pub count: &'a Buffer,
    pub count_offset: u64,
    /// Draws made at most, whatever the count says.
    pub max_draws: u32,
}

/// Records into one command buffer; created by [`Gpu::submit`].
pub struct Recorder<'a> {
    pub(crate) gpu: &'a Gpu,
    pub cmd: vk::CommandBuffer,
}

impl Recorder<'_> {
    /// Makes all earlier writes visible to all later reads and writes. Coarse on purpose: the
    /// passes here are long, and a wrong fine-grained barrier is a silent race.
    pub fn barrier(&self) {
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE)];
        let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
        // SAFETY: `self.cmd` is recording; a global memory barrier references no object.
        unsafe { self.gpu.device.cmd_pipeline_barrier2(self.cmd, &dep) };
    }

    /// Binds the pipeline, its resources (in slot order) and push constants.
    pub fn bind(&self, pipeline: &Pipeline, bindings: &[Binding], push: &[u8]) {
        assert_eq!(
            bindings.len(),
            pipeline.slots.len(),
            "pipeline '{}' takes {} bindings",
            pipeline.name,
            pipeline.slots.len()
        );
        assert!(push.len() <= PUSH_CONSTANT_BYTES as usize);
        let mut buffer_infos = Vec::with_capacity(bindings.len());
        let mut image_infos = Vec::with_capacity(bindings.len());
        let mut structures = Vec::new();
        for b in bindings {
            match *b {
                Binding::AccelerationStructure(s) => structures.push([s.handle]),
                Binding::Buffer(buf) => buffer_infos.push([vk::DescriptorBufferInfo {
                    buffer: buf.handle,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }]),
                Binding::Texture { image, linear } => image_infos.push([vk::DescriptorImageInfo {
                    sampler: if linear {
                        self.gpu.sampler_linear
                    } else {
                        self.gpu.sampler_nearest
                    },
                    image_view: image.view,
                    image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }]),
                Binding::StorageImage(image) => image_infos.push([vk::DescriptorImageInfo {
                    sampler: vk::Sampler::null(),
                    image_view: image.view,
                    image_layout: vk::ImageLayout::GENERAL,
                }]),
            }
        }
        let mut structure_writes: Vec<_> = structures
            .iter()
            .map(|s| {
                vk::WriteDescriptorSetAccelerationStructureKHR::default().acceleration_structures(s)
            })
            .collect();
        let mut structure_writes = structure_writes.iter_mut();
        let (mut bi, mut ii) = (0, 0);
        let writes: Vec<_> = bindings
            .iter()
            .zip(&pipeline.slots)
            .enumerate()
            .map(|(i, (b, slot))| {
                let w = vk::WriteDescriptorSet::default()
                    .dst_binding(i as u32)
                    .descriptor_type(slot_type(*slot));
                match b {
                    Binding::Buffer(_) => {
                        bi += 1;
                        w.buffer_info(&buffer_infos[bi - 1])
                    }
                    Binding::AccelerationStructure(_) => match structure_writes.next() {
                        // One write was made per structure binding, in the same order.
                        Some(structure) => w.descriptor_count(1).push_next(structure),
                        None => w,
                    },
                    _ => {
                        ii += 1;
                        w.image_info(&image_infos[ii - 1])
                    }
                }
            })
            .collect();
        // SAFETY: `self.cmd` is recording; the pipeline, its layout and the bound buffers and views
        // are live objects of this device, the writes match the pipeline's slots (asserted
        // above) and the push constants fit the layout's range.
        unsafe {
            let d = &self.gpu.device;
            d.cmd_bind_pipeline(self.cmd, pipeline.bind_point, pipeline.handle);
            if !writes.is_empty() {
                self.gpu.push_descriptor.cmd_push_descriptor_set(
                    self.cmd,
                    pipeline.bind_point,
                    pipeline.layout,
                    0,
                    &writes,
                );
            }
            if !push.is_empty() {
                d.cmd_push_constants(
                    self.cmd,
                    pipeline.layout,
                    vk::ShaderStageFlags::ALL,
                    0,
                    push,
                );
            }
        }
    }

    /// Dispatches enough workgroups to cover `threads` invocations per axis.
    pub fn dispatch(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        threads: [u32; 3],
    ) {
        let groups = [0, 1, 2].map(|i| threads[i].div_ceil(pipeline.local_size[i].max(1)));
        self.dispatch_groups(pipeline, bindings, push, groups);
    }

    pub fn dispatch_groups(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        groups: [u32; 3],
    ) {
        self.bind(pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording with a compute pipeline and its resources bound above.
        unsafe {
            self.gpu
                .device
                .cmd_dispatch(self.cmd, groups[0], groups[1], groups[2])
        };
    }

    /// Dispatches the workgroup counts stored as three `u32`s at `offset` in `args` (written
    /// by an earlier pass, e.g. from a count of generated work).
    pub fn dispatch_indirect(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        args: &Buffer,
        offset: u64,
    ) {
        self.bind(pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording with a compute pipeline bound above; `args` is a live
        // buffer of this device.
        unsafe {
            self.gpu
                .device
                .cmd_dispatch_indirect(self.cmd, args.handle, offset)
        };
    }

    /// Begins dynamic rendering into `target` (in `GENERAL` layout), cleared to `clear`.
    pub fn begin_rendering(&self, target: &Image, clear: [f32; 4]) {
        self.begin_rendering_with_depth(target, None, clear);
    }

    /// Like [`Recorder::begin_rendering`], with a depth attachment (in `GENERAL` layout)
    /// cleared to 1.0 when given.
    pub fn begin_rendering_with_depth(
        &self,
        target: &Image,
        depth: Option<&Image>,
        clear: [f32; 4],
    ) {
        self.begin_rendering_ops(target, depth, Some(clear));
    }

    /// Begins dynamic rendering; `clear: None` keeps the attachments' contents (to go on
    /// drawing into an image after a compute pass), otherwise colour is cleared to it and
    /// depth to 1.0.
    pub fn begin_rendering_ops(
        &self,
        target: &Image,
        depth: Option<&Image>,
        clear: Option<[f32; 4]>,
    ) {
        self.begin_rendering_inner(target, depth, clear, None);
    }

    /// Begins dynamic rendering into multisampled attachments (in `GENERAL` layout), cleared as
    /// [`Recorder::begin_rendering_with_depth`] does; at the end of rendering the colour
    /// samples are averaged into `resolve`, a single-sample image of the same size and format
    /// in `GENERAL` layout.
    pub fn begin_rendering_resolved(
        &self,
        target: &Image,
        depth: Option<&Image>,
        resolve: &Image,
        clear: [f32; 4],
    ) {
        self.begin_rendering_inner(target, depth, Some(clear), Some(resolve));
    }

    fn begin_rendering_inner(
        &self,
        target: &Image,
        depth: Option<&Image>,
        clear: Option<[f32; 4]>,
        resolve: Option<&Image>,
    ) {
        let load = if clear.is_some() {
            vk::AttachmentLoadOp::CLEAR
        } else {
            vk::AttachmentLoadOp::LOAD
        };
        let clear = clear.unwrap_or([0.0; 4]);
        let extent = vk::Extent2D {
            width: target.extent.width,
            height: target.extent.height,
        };
        let mut color = vk::RenderingAttachmentInfo::default()
            .image_view(target.view)
            .image_layout(vk::ImageLayout::GENERAL)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            });
        if let Some(r) = resolve {
            color = color
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(r.view)
                .resolve_image_layout(vk::ImageLayout::GENERAL);
        }
        let attachments = [color];
        let depth_attachment = depth.map(|d| {
            vk::RenderingAttachmentInfo::default()
                .image_view(d.view)
                .image_layout(vk::ImageLayout::GENERAL)
                .load_op(load)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue {
                        depth: 1.0,
                        stencil: 0,
                    },
                })
        });
        let mut info = vk::RenderingInfo::default()
            .render_area(extent.into())
            .layer_count(1)
            // Several layers mean one view per layer (multiview); the pipeline must match.
            .view_mask(if target.layers > 1 {
                (1 << target.layers) - 1
            } else {
                0
            })
            .color_attachments(&attachments);
        if let Some(d) = &depth_attachment {
            info = info.depth_attachment(d);
        }
        let viewport = [vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        }];
        // SAFETY: `self.cmd` is recording outside a render pass; the attachments are live images of
        // this device in `GENERAL` layout, as this function's contract asks.
        unsafe {
            let d = &self.gpu.device;
            d.cmd_begin_rendering(self.cmd, &info);
            d.cmd_set_viewport(self.cmd, 0, &viewport);
            d.cmd_set_scissor(self.cmd, 0, &[extent.into()]);
        }
    }

    /// Sets which faces the following draws cull, for pipelines made with
    /// `RenderTargets::dynamic_cull_mode` (front faces counter-clockwise in Vulkan's sense).
    pub fn set_cull_mode(&self, cull: vk::CullModeFlags) {
        // SAFETY: `self.cmd` is recording; the cull mode is dynamic state of Vulkan 1.3, the
        // version the device was made for.
        unsafe { self.gpu.device.cmd_set_cull_mode(self.cmd, cull) };
    }

    pub fn end_rendering(&self) {
        // SAFETY: `self.cmd` is recording inside the rendering begun by `begin_rendering*`.
        unsafe { self.gpu.device.cmd_end_rendering(self.cmd) };
    }

    pub fn draw(&self, pipeline: &Pipeline, bindings: &[Binding], push: &[u8], vertices: u32) {
        self.bind(pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording inside rendering, with the pipeline bound above.
        unsafe { self.gpu.device.cmd_draw(self.cmd, vertices, 1, 0, 0) };
    }

    /// One draw whose `VkDrawIndirectCommand` (vertex count, instance count, first vertex,
    /// first instance: four `u32`s) starts at `offset` in `args`, written by an earlier pass.
    pub fn draw_indirect(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        args: &Buffer,
        offset: u64,
    ) {
        self.bind(pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording inside rendering with the pipeline bound above;
        // `args` is a live buffer of this device.
        unsafe {
            self.gpu
                .device
                .cmd_draw_indirect(self.cmd, args.handle, offset, 1, 16)
        };
    }

    /// Indexed draws with 16-bit indices from `draws.indices`: `VkDrawIndexedIndirectCommand`s
    /// (index count, instance count, first index, vertex offset, first instance: five `u32`s)
    /// packed from `draws.commands_offset`, as many as the `u32` at `draws.count_offset` says
    /// (at most `draws.max_draws`), all written by earlier passes. The device must have
    /// [`crate::Capabilities::draw_indirect_count`].
    pub fn draw_indexed_indirect_count(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        draws: &IndexedDraws,
    ) -> Result<()> {
        let caps = self.gpu.caps();
        if !caps.draw_indirect_count || draws.max_draws > caps.max_draw_indirect_count {
            return Err(GpuError::Unsupported {
                device: caps.device_name.clone(),
                what: format!(
                    "{} indexed draws counted on the GPU (drawIndirectCount, multiDrawIndirect)",
                    draws.max_draws
                ),
            });
        }
        self.bind(pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording inside rendering with a graphics pipeline bound
        // above; the index, command and count buffers are live buffers of this device, and
        // the device has the features this draw needs (checked above).
        unsafe {
            let d = &self.gpu.device;
            d.cmd_bind_index_buffer(self.cmd, draws.indices.handle, 0, vk::IndexType::UINT16);
            d.cmd_draw_indexed_indirect_count(
                self.cmd,
                draws.commands.handle,
                draws.commands_offset,
                draws.count.handle,
                draws.count_offset,
                draws.max_draws,
                INDEXED_COMMAND_BYTES,
            );
        }
        Ok(())
    }

    /// Launches mesh-shader workgroups; the device must have `VK_EXT_mesh_shader`.
    pub fn draw_mesh_tasks(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        groups: [u32; 3],
    ) -> Result<()> {
        let mesh = self.mesh_shader()?;
        self.bind(pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording inside rendering with a mesh pipeline bound above, on a
        // device with `VK_EXT_mesh_shader` (checked by `mesh_shader`).
        unsafe { mesh.cmd_draw_mesh_tasks(self.cmd, groups[0], groups[1], groups[2]) };
        Ok(())
    }

    /// Launches the mesh-shader workgroups counted by a buffer: one draw whose
    /// `VkDrawMeshTasksIndirectCommandEXT` (three `u32` group counts) starts at `offset`.
    pub fn draw_mesh_tasks_indirect(
        &self,
        pipeline: &Pipeline,
        bindings: &[Binding],
        push: &[u8],
        args: &Buffer,
        offset: u64,
    ) -> Result<()> {
        let mesh = self.mesh_shader()?;
        self.bind(pipeline, bindings, push);
        // SAFETY: as for `draw_mesh_tasks`; `args` is a live buffer of this device.
        unsafe { mesh.cmd_draw_mesh_tasks_indirect(self.cmd, args.handle, offset, 1, 12) };
        Ok(())
    }

    fn mesh_shader(&self) -> Result<&ash::ext::mesh_shader::Device> {
        self.gpu
            .mesh_shader
            .as_ref()
            .ok_or_else(|| GpuError::Unsupported {
                device: self.gpu.caps().device_name.clone(),
                what: "VK_EXT_mesh_shader".into(),
            })
    }

    pub fn timestamp(&self, timer: &Timer, index: u32) {
        // SAFETY: `self.cmd` is recording and the timer's pool is a live timestamp pool of this
        // device; `scope` keeps `index` within its capacity.
        unsafe {
            self.gpu.device.cmd_write_timestamp2(
                self.cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                timer.pool,
                index,
            )
        };
    }
}

fn slot_type(slot: Slot) -> vk::DescriptorType {
    match slot {
        Slot::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
        Slot::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
        Slot::Texture => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        Slot::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
        Slot::AccelerationStructure => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
    }
}
