//! The logical device: which of the physical device's features and extensions Tessera turns
//! on (only those `caps` found).

use crate::caps::Capabilities;
use crate::context::Gpu;
use crate::error::{Result, VkContext};
use ash::vk;

impl Gpu {
    /// The device with one queue of `queue_family`, `extensions` enabled and every feature of
    /// `caps` that Tessera uses switched on.
    pub(crate) fn create_device(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        queue_family: u32,
        caps: &Capabilities,
        extensions: &[*const i8],
    ) -> Result<ash::Device> {
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        // SAFETY: `physical` was enumerated from this live instance.
        let supported = unsafe { instance.get_physical_device_features(physical) };
        let base = vk::PhysicalDeviceFeatures::default()
            .tessellation_shader(caps.tessellation)
            .shader_int64(supported.shader_int64 != 0)
            .fragment_stores_and_atomics(supported.fragment_stores_and_atomics != 0)
            .vertex_pipeline_stores_and_atomics(supported.vertex_pipeline_stores_and_atomics != 0)
            .shader_storage_image_write_without_format(
                supported.shader_storage_image_write_without_format != 0,
            )
            .pipeline_statistics_query(supported.pipeline_statistics_query != 0)
            .multi_draw_indirect(caps.draw_indirect_count);
        let mut v11 = vk::PhysicalDeviceVulkan11Features::default()
            .storage_buffer16_bit_access(true)
            .multiview(caps.multiview);
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default()
            .buffer_device_address(true)
            .shader_buffer_int64_atomics(caps.buffer_int64_atomics)
            .storage_buffer8_bit_access(true)
            .shader_int8(true)
            .scalar_block_layout(true)
            .host_query_reset(true)
            .descriptor_indexing(true)
            .runtime_descriptor_array(true)
            .draw_indirect_count(caps.draw_indirect_count);
        // Demotion is what `discard` compiles to for Vulkan 1.3 (a feature 1.3 requires).
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
            .shader_demote_to_helper_invocation(true)
            .dynamic_rendering(true)
            .synchronization2(true)
            .maintenance4(true);
        let mut mesh = vk::PhysicalDeviceMeshShaderFeaturesEXT::default()
            .mesh_shader(true)
            .task_shader(caps.task_shader)
            .multiview_mesh_shader(caps.mesh_multiview);
        let mut rtp =
            vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default().ray_tracing_pipeline(true);
        let mut accel = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut rq = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        let mut fatomic = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default()
            .shader_buffer_float32_atomic_add(caps.buffer_float32_atomic_add)
            .shader_buffer_float32_atomics(caps.buffer_float32_atomic_add)
            .shader_image_float32_atomic_add(caps.image_float32_atomic_add)
            .shader_image_float32_atomics(caps.image_float32_atomic_add);
        let mut img64 = vk::PhysicalDeviceShaderImageAtomicInt64FeaturesEXT::default()
            .shader_image_int64_atomics(true);
        let mut rep = vk::PhysicalDeviceRepresentativeFragmentTestFeaturesNV::default()
            .representative_fragment_test(true);
        let mut bary = vk::PhysicalDeviceFragmentShaderBarycentricFeaturesKHR::default()
            .fragment_shader_barycentric(true);
        let mut lock = vk::PhysicalDeviceFragmentShaderInterlockFeaturesEXT::default()
            .fragment_shader_pixel_interlock(true);
        let mut exe = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
            .pipeline_executable_info(true);
        let mut info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(extensions)
            .enabled_features(&base)
            .push_next(&mut v11)
            .push_next(&mut v12)
            .push_next(&mut v13);
        if caps.mesh_shader {
            info = info.push_next(&mut mesh);
        }
        if caps.ray_tracing_pipeline {
            info = info.push_next(&mut rtp);
        }
        if caps.acceleration_structure {
            info = info.push_next(&mut accel);
        }
        if caps.ray_query {
            info = info.push_next(&mut rq);
        }
        if caps.buffer_float32_atomic_add || caps.image_float32_atomic_add {
            info = info.push_next(&mut fatomic);
        }
        if caps.image_int64_atomics {
            info = info.push_next(&mut img64);
        }
        if caps.representative_fragment_test {
            info = info.push_next(&mut rep);
        }
        if caps.fragment_barycentric {
            info = info.push_next(&mut bary);
        }
        if caps.fragment_shader_interlock {
            info = info.push_next(&mut lock);
        }
        if caps.pipeline_executable_info {
            info = info.push_next(&mut exe);
        }
        // SAFETY: the create info, its feature chain and the extension names (static C
        // strings) all live until the call returns; only features the device reports are
        // enabled (see `caps`).
        unsafe { instance.create_device(physical, &info, None) }.call("vkCreateDevice")
    }
}
