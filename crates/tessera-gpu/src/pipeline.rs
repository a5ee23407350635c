//! Pipelines over one push-descriptor set and a push-constant block. Bindings are listed in
//! order (binding i = entry i), which keeps call sites free of descriptor bookkeeping.

use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use crate::shader::Spirv;
use crate::shared::{DeviceShared, Retired};
use ash::vk;
use std::ffi::CStr;
use std::sync::Arc;

/// Bytes of push constants every pipeline accepts: the guaranteed minimum on all devices.
pub const PUSH_CONSTANT_BYTES: u32 = 128;

/// Workgroups per axis every device accepts (the minimum Vulkan guarantees for compute, task
/// and mesh dispatches).
pub const MIN_GROUPS_PER_AXIS: u32 = 65_535;

/// Spreads a 1-D count of workgroups over x and y so x stays within `max_x` (a device's
/// `maxComputeWorkGroupCount[0]`, or [`MIN_GROUPS_PER_AXIS`] where no limit is known); shaders
/// recover the linear index as `gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x` and
/// skip indices past their count.
pub fn spread_groups(groups: u32, max_x: u32) -> [u32; 3] {
    let x = groups.clamp(1, max_x.max(1));
    [x, groups.max(1).div_ceil(x), 1]
}

/// What each binding slot holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    StorageBuffer,
    UniformBuffer,
    /// A combined image sampler (`sampler3D`/`sampler2D`).
    Texture,
    StorageImage,
    /// A top-level acceleration structure (ray-tracing pipelines).
    AccelerationStructure,
}

impl Slot {
    fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            Slot::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            Slot::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
            Slot::Texture => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            Slot::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
            Slot::AccelerationStructure => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
        }
    }
}

/// The layout and pipeline objects shared by every pipeline kind. Dropping it destroys them
/// (submissions that used it have finished: [`Gpu::submit`] waits); it keeps the device alive
/// meanwhile.
pub struct Pipeline {
    pub(crate) handle: vk::Pipeline,
    pub(crate) layout: vk::PipelineLayout,
    pub(crate) set_layout: vk::DescriptorSetLayout,
    pub(crate) bind_point: vk::PipelineBindPoint,
    pub(crate) slots: Vec<Slot>,
    /// Workgroup size of the compute shader (compute pipelines only).
    pub local_size: [u32; 3],
    pub name: String,
    shared: Arc<DeviceShared>,
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        self.shared.retire(Retired::Pipeline {
            pipeline: self.handle,
            layout: self.layout,
            set_layout: self.set_layout,
        });
    }
}

/// A shader module, destroyed when it goes out of scope (once its pipeline has been made).
pub(crate) struct Module<'a> {
    device: &'a ash::Device,
    pub(crate) handle: vk::ShaderModule,
}

impl Drop for Module<'_> {
    fn drop(&mut self) {
        // SAFETY: the module was created on this device and is only read by pipeline creation
        // calls, which have returned by the time it goes out of scope.
        unsafe { self.device.destroy_shader_module(self.handle, None) };
    }
}

const ENTRY: &CStr = c"main";

/// How a fragment's output combines with what the colour attachment holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blend {
    Replace,
    /// Sum per channel (order-independent accumulation).
    Add,
    /// Maximum per channel.
    Max,
}

/// The attachments a graphics pipeline renders into and how it treats them.
#[derive(Debug, Clone, Copy)]
pub struct RenderTargets {
    pub color_format: vk::Format,
    pub depth_format: Option<vk::Format>,
    /// How fragment outputs combine with the attachment.
    pub blend: Blend,
    /// With a depth format: whether passing fragments write depth (off for visibility tests
    /// against depth drawn earlier, which then also pass equal depths).
    pub depth_write: bool,
    /// Whether fragments write the colour attachment at all.
    pub color_write: bool,
    /// Let the rasterizer stop after one passing fragment per primitive
    /// (`VK_NV_representative_fragment_test`; ignored where the device lacks it). For
    /// visibility tests whose fragments only set a flag.
    pub representative_fragments: bool,
    /// Render to this many views at once with multiview (attachments with as many layers);
    /// 1 for ordinary rendering.
    pub views: u32,
    /// Rasterization samples per pixel (1 = no multisampling); the attachments must have as
    /// many, and the count must be one of [`Gpu::attachment_sample_counts`].
    pub samples: u32,
    /// Control points per patch when the shaders include tessellation stages (the topology is
    /// then `PATCH_LIST`); ignored otherwise.
    pub patch_control_points: u32,
    /// Whether the cull mode is set while recording ([`crate::Recorder::set_cull_mode`],
    /// before every draw with the pipeline); otherwise nothing is culled. Front faces are
    /// counter-clockwise in Vulkan's sense either way.
    pub dynamic_cull_mode: bool,
}

impl RenderTargets {
    /// Colour only, written and not blended.
    pub fn color(color_format: vk::Format) -> RenderTargets {
        RenderTargets {
            color_format,
            depth_format: None,
            blend: Blend::Replace,
            depth_write: false,
            color_write: true,
            representative_fragments: false,
            views: 1,
            samples: 1,
            patch_control_points: 1,
            dynamic_cull_mode: false,
        }
    }

    /// Colour plus a depth attachment that is tested (LESS) and written.
    pub fn color_depth(color_format: vk::Format, depth_format: vk::Format) -> RenderTargets {
        RenderTargets {
            depth_format: Some(depth_format),
            depth_write: true,
            ..RenderTargets::color(color_format)
        }
    }
}

/// `count` samples as Vulkan's flag, `None` unless a power of two from 1 to 64.
pub fn sample_count_flag(count: u32) -> Option<vk::SampleCountFlags> {
    (count.is_power_of_two() && count <= 64).then(|| vk::SampleCountFlags::from_raw(count))
}

impl Gpu {
    /// Sample counts usable for a colour attachment together with a depth attachment (the
    /// device's framebuffer limits for both), as a flag set.
    pub fn attachment_sample_counts(&self) -> vk::SampleCountFlags {
        // SAFETY: the physical device was enumerated from this live instance.
        let limits = unsafe {
            self.shared
                .instance
                .get_physical_device_properties(self.physical_device())
        }
        .limits;
        limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts
    }

    /// A pipeline whose set layout and layout exist and whose pipeline handle is still null,
    /// for the caller to create; dropping it on a failure destroys what was made.
    pub(crate) fn layout_for(
        &self,
        name: &str,
        bind_point: vk::PipelineBindPoint,
        slots: &[Slot],
        local_size: [u32; 3],
    ) -> Result<Pipeline> {
        let bindings: Vec<_> = slots
            .iter()
            .enumerate()
            .map(|(i, s)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(s.descriptor_type())
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::ALL)
            })
            .collect();
        let set_info = vk::DescriptorSetLayoutCreateInfo::default()
            .flags(vk::DescriptorSetLayoutCreateFlags::PUSH_DESCRIPTOR_KHR)
            .bindings(&bindings);
        let mut pipeline = Pipeline {
            handle: vk::Pipeline::null(),
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            bind_point,
            slots: slots.to_vec(),
            local_size,
            name: name.into(),
            shared: self.shared.clone(),
        };
        // SAFETY: the create info and the bindings it points at outlive the call; push
        // descriptors are enabled on the device (`VK_KHR_push_descriptor` is required).
        pipeline.set_layout = unsafe { self.device.create_descriptor_set_layout(&set_info, None) }
            .call("vkCreateDescriptorSetLayout")?;
        let ranges = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::ALL,
            offset: 0,
            size: PUSH_CONSTANT_BYTES,
        }];
        let set_layouts = [pipeline.set_layout];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&ranges);
        // SAFETY: the set layout is live and the push-constant range is within the minimum
        // every device supports.
        pipeline.layout = unsafe { self.device.create_pipeline_layout(&info, None) }
            .call("vkCreatePipelineLayout")?;
        Ok(pipeline)
    }

    pub(crate) fn module(&self, spirv: &Spirv) -> Result<Module<'_>> {
        let info = vk::ShaderModuleCreateInfo::default().code(&spirv.words);
        // SAFETY: `words` is SPIR-V produced by the shader compiler (a whole number of 32-bit
        // words), alive for the call.
        let handle = unsafe { self.device.create_shader_module(&info, None) }
            .call("vkCreateShaderModule")?;
        let module = Module {
            device: &self.device,
            handle,
        };
        self.set_name(handle, &spirv.path);
        Ok(module)
    }

    pub fn compute_pipeline(&self, name: &str, shader: &Spirv, slots: &[Slot]) -> Result<Pipeline> {
        let local_size = shader.local_size()?;
        let mut pipeline =
            self.layout_for(name, vk::PipelineBindPoint::COMPUTE, slots, local_size)?;
        let module = self.module(shader)?;
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.handle)
            .name(ENTRY);
        let flags = if self.captures_pipeline_statistics() {
            vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR
        } else {
            vk::PipelineCreateFlags::empty()
        };
        let info = [vk::ComputePipelineCreateInfo::default()
            .flags(flags)
            .stage(stage)
            .layout(pipeline.layout)];
        // SAFETY: the create info, the live module and layout it names and the entry-point
        // name outlive the call.
        let result = unsafe {
            self.device
                .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
        };
        drop(module);
        pipeline.handle = result
            .map_err(|(_, e)| e)
            .call("vkCreateComputePipelines")?[0];
        self.set_name(pipeline.handle, name);
        self.capture_statistics(name, pipeline.handle);
        Ok(pipeline)
    }

    /// A graphics pipeline drawing into one colour attachment of `color_format` with dynamic
    /// rendering. `shaders` is either vertex+fragment or (task+)mesh+fragment.
    pub fn graphics_pipeline(
        &self,
        name: &str,
        shaders: &[&Spirv],
        slots: &[Slot],
        color_format: vk::Format,
        blend_additive: bool,
    ) -> Result<Pipeline> {
        let targets = RenderTargets {
            blend: if blend_additive {
                Blend::Add
            } else {
                Blend::Replace
            },
            ..RenderTargets::color(color_format)
        };
        self.graphics_pipeline_for(name, shaders, slots, &targets)
    }

    /// A graphics pipeline for the attachments described by `targets`; with a depth format it
    /// tests and writes depth with LESS. `shaders` is vertex(+tessellation control and
    /// evaluation)+fragment or (task+)mesh+fragment.
    pub fn graphics_pipeline_for(
        &self,
        name: &str,
        shaders: &[&Spirv],
        slots: &[Slot],
        targets: &RenderTargets,
    ) -> Result<Pipeline> {
        // Checked before any object is made, so that a refusal leaks nothing.
        let samples = sample_count_flag(targets.samples)
            .filter(|&f| self.attachment_sample_counts().contains(f))
            .ok_or_else(|| GpuError::Unsupported {
                device: self.caps().device_name.clone(),
                what: format!("{} samples per pixel for '{name}'", targets.samples),
            })?;
        let color_format = targets.color_format;
        let blend_op = match targets.blend {
            Blend::Max => vk::BlendOp::MAX,
            _ => vk::BlendOp::ADD,
        };
        let mut pipeline = self.layout_for(name, vk::PipelineBindPoint::GRAPHICS, slots, [0; 3])?;
        let mut modules = Vec::new();
        for s in shaders {
            modules.push(self.module(s)?);
        }
        let stages: Vec<_> = shaders
            .iter()
            .zip(&modules)
            .map(|(s, m)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(stage_flag(s.stage))
                    .module(m.handle)
                    .name(ENTRY)
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(samples);
        let attachment = [vk::PipelineColorBlendAttachmentState::default()
            .blend_enable(targets.blend != Blend::Replace)
            .src_color_blend_factor(vk::BlendFactor::ONE)
            .dst_color_blend_factor(vk::BlendFactor::ONE)
            .color_blend_op(blend_op)
            .src_alpha_blend_factor(vk::BlendFactor::ONE)
            .dst_alpha_blend_factor(vk::BlendFactor::ONE)
            .alpha_blend_op(blend_op)
            .color_write_mask(if targets.color_write {
                vk::ColorComponentFlags::RGBA
            } else {
                vk::ColorComponentFlags::empty()
            })];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachment);
        let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if targets.dynamic_cull_mode {
            dynamic_states.push(vk::DynamicState::CULL_MODE);
        }
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let formats = [color_format];
        let mut rendering =
            vk::PipelineRenderingCreateInfo::default().color_attachment_formats(&formats);
        let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(targets.depth_write)
            .depth_compare_op(if targets.depth_write {
                vk::CompareOp::LESS
            } else {
                vk::CompareOp::LESS_OR_EQUAL
            });
        if let Some(depth) = targets.depth_format {
            rendering = rendering.depth_attachment_format(depth);
        }
        if targets.views > 1 {
            rendering = rendering.view_mask((1 << targets.views) - 1);
        }
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(pipeline.layout)
            .push_next(&mut rendering);
        let uses_vertex = shaders
            .iter()
            .any(|s| s.stage == crate::shader::Stage::Vertex);
        let tessellated = shaders
            .iter()
            .any(|s| s.stage == crate::shader::Stage::TessControl);
        let patch_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::PATCH_LIST);
        let tessellation = vk::PipelineTessellationStateCreateInfo::default()
            .patch_control_points(targets.patch_control_points);
        if targets.depth_format.is_some() {
            info = info.depth_stencil_state(&depth_stencil);
        }
        let mut representative = vk::PipelineRepresentativeFragmentTestStateCreateInfoNV::default()
            .representative_fragment_test_enable(true);
        if targets.representative_fragments && self.caps().representative_fragment_test {
            info = info.push_next(&mut representative);
        }
        if uses_vertex {
            info = info
                .vertex_input_state(&vertex_input)
                .input_assembly_state(if tessellated {
                    &patch_assembly
                } else {
                    &assembly
                });
        }
        if tessellated {
            info = info.tessellation_state(&tessellation);
        }
        // SAFETY: the create info and everything its chain points at (stages, states, live
        // modules and layout, formats) live until the call returns; optional structures are
        // chained only when the device has the matching feature.
        let result = unsafe {
            self.device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        };
        drop(modules);
        pipeline.handle = result
            .map_err(|(_, e)| e)
            .call("vkCreateGraphicsPipelines")?[0];
        self.set_name(pipeline.handle, name);
        Ok(pipeline)
    }
}

fn stage_flag(stage: crate::shader::Stage) -> vk::ShaderStageFlags {
    use crate::shader::Stage::*;
    match stage {
        Vertex => vk::ShaderStageFlags::VERTEX,
        TessControl => vk::ShaderStageFlags::TESSELLATION_CONTROL,
        TessEval => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        Fragment => vk::ShaderStageFlags::FRAGMENT,
        Compute => vk::ShaderStageFlags::COMPUTE,
        Task => vk::ShaderStageFlags::TASK_EXT,
        Mesh => vk::ShaderStageFlags::MESH_EXT,
        RayGen => vk::ShaderStageFlags::RAYGEN_KHR,
        ClosestHit => vk::ShaderStageFlags::CLOSEST_HIT_KHR,
        Miss => vk::ShaderStageFlags::MISS_KHR,
        AnyHit => vk::ShaderStageFlags::ANY_HIT_KHR,
        Intersection => vk::ShaderStageFlags::INTERSECTION_KHR,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_groups_covers_the_count_within_the_axis_limit() {
        let m = MIN_GROUPS_PER_AXIS;
        assert_eq!(spread_groups(0, m), [1, 1, 1]);
        assert_eq!(spread_groups(65_535, m), [65_535, 1, 1]);
        assert_eq!(spread_groups(65_536, m), [65_535, 2, 1]);
        assert_eq!(spread_groups(10, 4), [4, 3, 1]);
        for n in [1u32, 1000, 200_000, 4_000_000] {
            let [x, y, _] = spread_groups(n, m);
            assert!(x <= MIN_GROUPS_PER_AXIS && y <= MIN_GROUPS_PER_AXIS);
            assert!(x as u64 * y as u64 >= n as u64 && (x as u64) * (y as u64 - 1) < n as u64);
        }
    }
}
