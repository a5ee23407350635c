//! Ray-tracing pipelines over the same push-descriptor set and push constants as every other
//! pipeline, with their shader binding table: one ray-generation shader, miss shaders, and
//! procedural hit groups (intersection shader, optional any-hit and closest-hit shaders).
//! Shaders select a hit group with `traceRayEXT`'s record offset (stride 0: one geometry).

use crate::commands::{Binding, Recorder};
use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use crate::memory::Buffer;
use crate::pipeline::{Pipeline, Slot};
use crate::shader::{Spirv, Stage};
use ash::vk;

/// A hit group for box primitives.
#[derive(Clone, Copy)]
pub struct ProceduralHitGroup<'a> {
    pub intersection: &'a Spirv,
    pub any_hit: Option<&'a Spirv>,
    pub closest_hit: Option<&'a Spirv>,
}

/// The shaders of a ray-tracing pipeline.
#[derive(Clone, Copy)]
pub struct RayTracingShaders<'a> {
    pub ray_generation: &'a Spirv,
    pub misses: &'a [&'a Spirv],
    pub hit_groups: &'a [ProceduralHitGroup<'a>],
}

/// A ray-tracing pipeline and its shader binding table; frees both when dropped.
pub struct RayTracingPipeline {
    pipeline: Pipeline,
    /// Holds the group handles the regions below point into.
    _table: Buffer,
    ray_generation: vk::StridedDeviceAddressRegionKHR,
    miss: vk::StridedDeviceAddressRegionKHR,
    hit: vk::StridedDeviceAddressRegionKHR,
}

/// The shader-group handle sizes and alignments of a device.
#[derive(Debug, Clone, Copy)]
struct GroupLayout {
    handle_size: u64,
    handle_alignment: u64,
    base_alignment: u64,
}

impl GroupLayout {
    fn stride(&self) -> u64 {
        self.handle_size.next_multiple_of(self.handle_alignment)
    }

    /// Byte offsets of the three regions (ray generation, miss, hit) and the table's size, for
    /// `misses` and `hits` records.
    fn regions(&self, misses: u64, hits: u64) -> ([u64; 3], u64) {
        let stride = self.stride();
        let generation_bytes = stride.next_multiple_of(self.base_alignment);
        let miss_bytes = (misses * stride).next_multiple_of(self.base_alignment);
        let hit_bytes = (hits * stride).next_multiple_of(self.base_alignment);
        (
            [0, generation_bytes, generation_bytes + miss_bytes],
            generation_bytes + miss_bytes + hit_bytes,
        )
    }
}

fn stage_info(
    module: vk::ShaderModule,
    stage: vk::ShaderStageFlags,
) -> vk::PipelineShaderStageCreateInfo<'static> {
    vk::PipelineShaderStageCreateInfo::default()
        .stage(stage)
        .module(module)
        .name(c"main")
}

impl Gpu {
    fn ray_tracing(&self) -> Result<&ash::khr::ray_tracing_pipeline::Device> {
        self.ray_tracing
            .as_ref()
            .ok_or_else(|| GpuError::Unsupported {
                device: self.caps().device_name.clone(),
                what: "VK_KHR_ray_tracing_pipeline".into(),
            })
    }

    fn group_layout(&self) -> GroupLayout {
        let mut rt = vk::PhysicalDeviceRayTracingPipelinePropertiesKHR::default();
        self.chained_properties(&mut rt);
        GroupLayout {
            handle_size: u64::from(rt.shader_group_handle_size),
            handle_alignment: u64::from(rt.shader_group_handle_alignment.max(1)),
            base_alignment: u64::from(rt.shader_group_base_alignment.max(1)),
        }
    }

    /// A ray-tracing pipeline (rays traced one level deep: no shader traces further) binding
    /// `slots` in order, with its shader binding table.
    pub fn ray_tracing_pipeline(
        &self,
        name: &str,
        shaders: &RayTracingShaders,
        slots: &[Slot],
    ) -> Result<RayTracingPipeline> {
        let loader = self.ray_tracing()?;
        let expect = |spirv: &Spirv, stage: Stage| {
            if spirv.stage == stage {
                Ok(())
            } else {
                Err(GpuError::Invalid(format!(
                    "ray-tracing pipeline '{name}': {} is a {:?} shader where a {stage:?} one belongs",
                    spirv.path, spirv.stage
                )))
            }
        };
        expect(shaders.ray_generation, Stage::RayGen)?;
        for miss in shaders.misses {
            expect(miss, Stage::Miss)?;
        }
        for group in shaders.hit_groups {
            expect(group.intersection, Stage::Intersection)?;
            if let Some(any_hit) = group.any_hit {
                expect(any_hit, Stage::AnyHit)?;
            }
            if let Some(closest) = group.closest_hit {
                expect(closest, Stage::ClosestHit)?;
            }
        }
        let mut pipeline =
            self.layout_for(name, vk::PipelineBindPoint::RAY_TRACING_KHR, slots, [0; 3])?;
        let mut modules = Vec::new();
        let mut stages = Vec::new();
        let mut add = |spirv: &Spirv, stage: vk::ShaderStageFlags| -> Result<u32> {
            let module = self.module(spirv)?;
            stages.push(stage_info(module.handle, stage));
            modules.push(module);
            Ok(stages.len() as u32 - 1)
        };
        let general = |shader: u32| {
            vk::RayTracingShaderGroupCreateInfoKHR::default()
                .ty(vk::RayTracingShaderGroupTypeKHR::GENERAL)
                .general_shader(shader)
                .closest_hit_shader(vk::SHADER_UNUSED_KHR)
                .any_hit_shader(vk::SHADER_UNUSED_KHR)
                .intersection_shader(vk::SHADER_UNUSED_KHR)
        };
        let mut groups = vec![general(add(
            shaders.ray_generation,
            vk::ShaderStageFlags::RAYGEN_KHR,
        )?)];
        for miss in shaders.misses {
            groups.push(general(add(miss, vk::ShaderStageFlags::MISS_KHR)?));
        }
        for group in shaders.hit_groups {
            let intersection = add(group.intersection, vk::ShaderStageFlags::INTERSECTION_KHR)?;
            let any_hit = match group.any_hit {
                Some(s) => add(s, vk::ShaderStageFlags::ANY_HIT_KHR)?,
                None => vk::SHADER_UNUSED_KHR,
            };
            let closest = match group.closest_hit {
                Some(s) => add(s, vk::ShaderStageFlags::CLOSEST_HIT_KHR)?,
                None => vk::SHADER_UNUSED_KHR,
            };
            groups.push(
                vk::RayTracingShaderGroupCreateInfoKHR::default()
                    .ty(vk::RayTracingShaderGroupTypeKHR::PROCEDURAL_HIT_GROUP)
                    .general_shader(vk::SHADER_UNUSED_KHR)
                    .intersection_shader(intersection)
                    .any_hit_shader(any_hit)
                    .closest_hit_shader(closest),
            );
        }
        let info = [vk::RayTracingPipelineCreateInfoKHR::default()
            .stages(&stages)
            .groups(&groups)
            .max_pipeline_ray_recursion_depth(1)
            .layout(pipeline.layout)];
        // SAFETY: the create info, its stages (live modules, entry-point names), groups and
        // the live layout outlive the call; the device has the ray-tracing pipeline feature
        // (`ray_tracing()` found the loader).
        let result = unsafe {
            loader.create_ray_tracing_pipelines(
                vk::DeferredOperationKHR::null(),
                vk::PipelineCache::null(),
                &info,
                None,
            )
        };
        drop(modules);
        pipeline.handle = result
            .map_err(|(_, e)| e)
            .call("vkCreateRayTracingPipelinesKHR")?[0];
        self.set_name(pipeline.handle, name);

        let layout = self.group_layout();
        let handle_size = layout.handle_size as usize;
        // SAFETY: the pipeline is live and has `groups.len()` groups; the data size is that
        // many handles.
        let handles = unsafe {
            loader.get_ray_tracing_shader_group_handles(
                pipeline.handle,
                0,
                groups.len() as u32,
                groups.len() * handle_size,
            )
        }
        .call("vkGetRayTracingShaderGroupHandlesKHR")?;
        let misses = shaders.misses.len() as u64;
        let hits = shaders.hit_groups.len() as u64;
        let (offsets, bytes) = layout.regions(misses, hits);
        let stride = layout.stride();
        let mut table = vec![0u8; bytes as usize];
        let mut place = |group: usize, at: u64| {
            let handle = &handles[group * handle_size..(group + 1) * handle_size];
            table[at as usize..at as usize + handle_size].copy_from_slice(handle);
        };
        place(0, offsets[0]);
        for m in 0..misses {
            place(1 + m as usize, offsets[1] + m * stride);
        }
        for h in 0..hits {
            place(1 + (misses + h) as usize, offsets[2] + h * stride);
        }
        // The buffer's own address must meet the base alignment too: allocate spare bytes and
        // start the table at the first aligned address.
        let spare = layout.base_alignment;
        let mut padded = vec![0u8; spare as usize + table.len()];
        let buffer = self.create_buffer(
            &format!("{name} binding table"),
            padded.len() as u64,
            vk::BufferUsageFlags::SHADER_BINDING_TABLE_KHR | vk::BufferUsageFlags::TRANSFER_DST,
            crate::memory::MemoryLocation::GpuOnly,
        )?;
        let address = self.buffer_address(&buffer);
        let skip = address.next_multiple_of(layout.base_alignment) - address;
        padded[skip as usize..skip as usize + table.len()].copy_from_slice(&table);
        self.write_buffer(&buffer, &padded)?;
        let base = address + skip;
        let region = |offset: u64, count: u64| vk::StridedDeviceAddressRegionKHR {
            device_address: if count == 0 { 0 } else { base + offset },
            stride: if count == 0 { 0 } else { stride },
            size: count * stride,
        };
        // The ray-generation region's size must equal its stride.
        let ray_generation = vk::StridedDeviceAddressRegionKHR {
            device_address: base,
            stride: stride.next_multiple_of(layout.base_alignment),
            size: stride.next_multiple_of(layout.base_alignment),
        };
        Ok(RayTracingPipeline {
            pipeline,
            _table: buffer,
            ray_generation,
            miss: region(offsets[1], misses),
            hit: region(offsets[2], hits),
        })
    }
}

impl Recorder<'_> {
    /// Launches `size` ray-generation invocations of `pipeline` with `bindings` (in slot
    /// order) and `push` constants.
    pub fn trace_rays(
        &self,
        pipeline: &RayTracingPipeline,
        bindings: &[Binding],
        push: &[u8],
        size: [u32; 3],
    ) -> Result<()> {
        let loader = self.gpu.ray_tracing()?;
        self.bind(&pipeline.pipeline, bindings, push);
        // SAFETY: `self.cmd` is recording with the ray-tracing pipeline and its resources bound
        // above; the regions point into the pipeline's live binding table, laid out with the
        // device's handle size and alignments.
        unsafe {
            loader.cmd_trace_rays(
                self.cmd,
                &pipeline.ray_generation,
                &pipeline.miss,
                &pipeline.hit,
                &vk::StridedDeviceAddressRegionKHR::default(),
                size[0],
                size[1],
                size[2],
            )
        };
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_start_on_the_base_alignment_and_hold_every_record() {
        let layout = GroupLayout {
            handle_size: 32,
            handle_alignment: 32,
            base_alignment: 64,
        };
        let (offsets, bytes) = layout.regions(1, 3);
        assert_eq!(offsets, [0, 64, 128]);
        assert_eq!(bytes, 128 + 128);
        let odd = GroupLayout {
            handle_size: 24,
            handle_alignment: 8,
            base_alignment: 16,
        };
        assert_eq!(odd.stride(), 24);
        let (offsets, bytes) = odd.regions(2, 1);
        assert_eq!(offsets, [0, 32, 80]);
        assert_eq!(bytes, 80 + 32);
    }
}
