//! What a physical device can do, read once at start-up. Techniques choose their path from this,
//! and `tessera info` prints it.

use ash::vk;
use std::ffi::CStr;

/// Capabilities that decide which technique paths can run (DESIGN §3's table).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Capabilities {
    pub device_name: String,
    pub device_type: String,
    pub driver_name: String,
    pub driver_info: String,
    pub api_version: String,
    pub vendor_id: u32,
    pub mesh_shader: bool,
    pub task_shader: bool,
    pub mesh_max_output_vertices: u32,
    pub mesh_max_output_primitives: u32,
    pub mesh_max_payload_bytes: u32,
    pub mesh_preferred_invocations: u32,
    pub mesh_multiview: bool,
    /// Rendering several views in one pass (`multiview`, core in Vulkan 1.1).
    pub multiview: bool,
    pub ray_tracing_pipeline: bool,
    pub acceleration_structure: bool,
    pub ray_query: bool,
    pub tessellation: bool,
    pub max_tessellation_level: u32,
    pub buffer_int64_atomics: bool,
    pub image_int64_atomics: bool,
    pub buffer_float32_atomic_add: bool,
    pub image_float32_atomic_add: bool,
    pub subgroup_size: u32,
    pub subgroup_arithmetic: bool,
    /// Subgroup ballot and shuffle operations in compute shaders.
    pub subgroup_ballot_and_shuffle: bool,
    pub representative_fragment_test: bool,
    pub fragment_barycentric: bool,
    pub fragment_shader_interlock: bool,
    pub timestamp_period_ns: f32,
    pub device_local_bytes: u64,
    pub max_image_dimension_3d: u32,
    /// Fractional bits of rasterizer vertex positions: graphics-path attributes are exact only
    /// for the triangle with its corners snapped to 2^-bits pixel.
    pub sub_pixel_precision_bits: u32,
    pub max_storage_buffer_range: u64,
    /// `VK_KHR_pipeline_executable_properties`: the driver can report registers and the like
    /// per compiled pipeline.
    pub pipeline_executable_info: bool,
    pub max_compute_workgroup_invocations: u32,
    /// Most workgroups one dispatch may launch along x, y and z.
    pub max_compute_workgroup_count: [u32; 3],
    /// Indirect draws whose count a buffer holds, many per call (`drawIndirectCount` and
    /// `multiDrawIndirect`).
    pub draw_indirect_count: bool,
    /// Most draws one indirect draw call may make.
    pub max_draw_indirect_count: u32,
}

impl Capabilities {
    pub fn is_cpu(&self) -> bool {
        self.device_type == "cpu"
    }
}

pub(crate) fn has_extension(available: &[vk::ExtensionProperties], name: &CStr) -> bool {
    available
        .iter()
        .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
}

fn device_type_name(t: vk::PhysicalDeviceType) -> &'static str {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual",
        vk::PhysicalDeviceType::CPU => "cpu",
        _ => "other",
    }
}

/// Whether compute shaders have every subgroup operation in `operations`.
fn compute_subgroups(
    v11: &vk::PhysicalDeviceVulkan11Properties,
    operations: vk::SubgroupFeatureFlags,
) -> bool {
    v11.subgroup_supported_operations.contains(operations)
        && v11
            .subgroup_supported_stages
            .contains(vk::ShaderStageFlags::COMPUTE)
}

/// Reads features and properties through the `*2` queries. Extension structs are chained only
/// when the extension exists, since some drivers reject unknown structs in the chain.
pub(crate) fn query(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    extensions: &[vk::ExtensionProperties],
) -> Capabilities {
    let has = |n: &CStr| has_extension(extensions, n);
    let mut mesh_f = vk::PhysicalDeviceMeshShaderFeaturesEXT::default();
    let mut rtp_f = vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default();
    let mut as_f = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut rq_f = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut fatomic_f = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default();
    let mut img64_f = vk::PhysicalDeviceShaderImageAtomicInt64FeaturesEXT::default();
    let mut rep_f = vk::PhysicalDeviceRepresentativeFragmentTestFeaturesNV::default();
    let mut bary_f = vk::PhysicalDeviceFragmentShaderBarycentricFeaturesKHR::default();
    let mut lock_f = vk::PhysicalDeviceFragmentShaderInterlockFeaturesEXT::default();
    let mut exe_f = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default();
    let mut v11_f = vk::PhysicalDeviceVulkan11Features::default();
    let mut v12_f = vk::PhysicalDeviceVulkan12Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut v11_f)
        .push_next(&mut v12_f);
    if has(ash::ext::mesh_shader::NAME) {
        features = features.push_next(&mut mesh_f);
    }
    if has(ash::khr::ray_tracing_pipeline::NAME) {
        features = features.push_next(&mut rtp_f);
    }
    if has(ash::khr::acceleration_structure::NAME) {
        features = features.push_next(&mut as_f);
    }
    if has(ash::khr::ray_query::NAME) {
        features = features.push_next(&mut rq_f);
    }
    if has(ash::ext::shader_atomic_float::NAME) {
        features = features.push_next(&mut fatomic_f);
    }
    if has(ash::ext::shader_image_atomic_int64::NAME) {
        features = features.push_next(&mut img64_f);
    }
    if has(ash::nv::representative_fragment_test::NAME) {
        features = features.push_next(&mut rep_f);
    }
    if has(ash::khr::fragment_shader_barycentric::NAME) {
        features = features.push_next(&mut bary_f);
    }
    if has(ash::ext::fragment_shader_interlock::NAME) {
        features = features.push_next(&mut lock_f);
    }
    if has(ash::khr::pipeline_executable_properties::NAME) {
        features = features.push_next(&mut exe_f);
    }
    // SAFETY: `physical` was enumerated from this live instance and `features` is a valid chain
    // of structures that live until the call returns.
    unsafe { instance.get_physical_device_features2(physical, &mut features) };
    let base_f = features.features;

    let mut mesh_p = vk::PhysicalDeviceMeshShaderPropertiesEXT::default();
    let mut v11_p = vk::PhysicalDeviceVulkan11Properties::default();
    let mut v12_p = vk::PhysicalDeviceVulkan12Properties::default();
    let mut props = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut v11_p)
        .push_next(&mut v12_p);
    if has(ash::ext::mesh_shader::NAME) {
        props = props.push_next(&mut mesh_p);
    }
    // SAFETY: as above, for the properties chain.
    unsafe { instance.get_physical_device_properties2(physical, &mut props) };
    let p = props.properties;
    // SAFETY: `physical` was enumerated from this live instance.
    let memory = unsafe { instance.get_physical_device_memory_properties(physical) };
    let device_local_bytes = memory.memory_heaps[..memory.memory_heap_count as usize]
        .iter()
        .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
        .map(|h| h.size)
        .max()
        .unwrap_or(0);
    let text = |c: Result<&CStr, _>| {
        c.map(|s: &CStr| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let v = p.api_version;
    Capabilities {
        device_name: text(p.device_name_as_c_str()),
        device_type: device_type_name(p.device_type).to_string(),
        driver_name: text(v12_p.driver_name_as_c_str()),
        driver_info: text(v12_p.driver_info_as_c_str()),
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
        vendor_id: p.vendor_id,
        mesh_shader: mesh_f.mesh_shader != 0,
        task_shader: mesh_f.task_shader != 0,
        mesh_max_output_vertices: mesh_p.max_mesh_output_vertices,
        mesh_max_output_primitives: mesh_p.max_mesh_output_primitives,
        mesh_max_payload_bytes: mesh_p.max_task_payload_size,
        mesh_preferred_invocations: mesh_p.max_preferred_mesh_work_group_invocations,
        mesh_multiview: mesh_f.multiview_mesh_shader != 0 && v11_f.multiview != 0,
        multiview: v11_f.multiview != 0,
        ray_tracing_pipeline: rtp_f.ray_tracing_pipeline != 0,
        acceleration_structure: as_f.acceleration_structure != 0,
        ray_query: rq_f.ray_query != 0,
        tessellation: base_f.tessellation_shader != 0,
        max_tessellation_level: p.limits.max_tessellation_generation_level,
        buffer_int64_atomics: v12_f.shader_buffer_int64_atomics != 0,
        image_int64_atomics: img64_f.shader_image_int64_atomics != 0,
        buffer_float32_atomic_add: fatomic_f.shader_buffer_float32_atomic_add != 0,
        image_float32_atomic_add: fatomic_f.shader_image_float32_atomic_add != 0,
        subgroup_size: v11_p.subgroup_size,
        subgroup_arithmetic: compute_subgroups(&v11_p, vk::SubgroupFeatureFlags::ARITHMETIC),
        subgroup_ballot_and_shuffle: compute_subgroups(
            &v11_p,
            vk::SubgroupFeatureFlags::BALLOT | vk::SubgroupFeatureFlags::SHUFFLE,
        ),
        representative_fragment_test: rep_f.representative_fragment_test != 0,
        fragment_barycentric: bary_f.fragment_shader_barycentric != 0,
        fragment_shader_interlock: lock_f.fragment_shader_pixel_interlock != 0,
        timestamp_period_ns: p.limits.timestamp_period,
        device_local_bytes,
        max_image_dimension_3d: p.limits.max_image_dimension3_d,
        sub_pixel_precision_bits: p.limits.sub_pixel_precision_bits,
        max_storage_buffer_range: p.limits.max_storage_buffer_range as u64,
        pipeline_executable_info: exe_f.pipeline_executable_info != 0,
        max_compute_workgroup_invocations: p.limits.max_compute_work_group_invocations,
        max_compute_workgroup_count: p.limits.max_compute_work_group_count,
        draw_indirect_count: v12_f.draw_indirect_count != 0 && base_f.multi_draw_indirect != 0,
        max_draw_indirect_count: p.limits.max_draw_indirect_count,
    }
}
