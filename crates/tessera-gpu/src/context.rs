//! Instance, device and queue: the one object every other part of the plumbing borrows.

use crate::caps::{self, has_extension, Capabilities};
use crate::error::{GpuError, Result, VkContext};
use crate::shared::DeviceShared;
pub use crate::validation::ValidationLog;
use crate::validation::{create_messenger, VALIDATION_LAYER};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::cell::Cell;
use std::ffi::{CStr, CString};
use std::marker::PhantomData;
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, AtomicU32};
use std::sync::{Arc, Mutex};

/// How to open the device.
#[derive(Debug, Clone, Default)]
pub struct GpuOptions {
    /// Index into the enumeration order printed by `tessera info`; `None` picks the best device
    /// (discrete, then integrated, then anything else).
    pub device_index: Option<usize>,
    /// Enables the Khronos validation layer and counts its error messages.
    pub validation: bool,
    /// The longest one submission may run before [`crate::Gpu::submit`] gives up on it with
    /// [`crate::GpuError::Timeout`] (an endless loop in a user's shader function, say); `None`
    /// waits for ever. After a timeout the device is unusable and is not destroyed.
    pub timeout: Option<std::time::Duration>,
    /// Captures what the driver reports of each compute pipeline (registers, shared memory…)
    /// where it can ([`Gpu::pipeline_statistics`]); for performance work.
    pub pipeline_statistics: bool,
}

/// A physical device as listed for the user, before one is opened.
#[derive(Debug, Clone)]
pub struct DeviceListing {
    pub index: usize,
    pub name: String,
    pub device_type: String,
}

/// The opened device with its queue, command pool, samplers and extension loaders. The device
/// itself, its allocator and the instance live in a shared part that every object made from it
/// also holds, so objects may outlive this handle (they free themselves when dropped).
pub struct Gpu {
    /// The same device as `shared.device` (a table of function pointers, cheap to clone).
    pub(crate) device: ash::Device,
    pub(crate) shared: Arc<DeviceShared>,
    pub(crate) queue: vk::Queue,
    /// The queue's family, which presenting to a surface asks about (`window` feature).
    #[cfg_attr(not(feature = "window"), allow(dead_code))]
    pub(crate) queue_family: u32,
    pub(crate) command_pool: vk::CommandPool,
    pub(crate) push_descriptor: ash::khr::push_descriptor::Device,
    pub(crate) mesh_shader: Option<ash::ext::mesh_shader::Device>,
    pub(crate) ray_tracing: Option<ash::khr::ray_tracing_pipeline::Device>,
    /// Present when pipelines are created with their statistics captured.
    pub(crate) pipeline_executables: Option<ash::khr::pipeline_executable_properties::Device>,
    pub(crate) debug_device: Option<ash::ext::debug_utils::Device>,
    /// Clamp-to-edge samplers shared by every texture binding.
    pub(crate) sampler_nearest: vk::Sampler,
    pub(crate) sampler_linear: vk::Sampler,
    caps: Capabilities,
    physical: vk::PhysicalDevice,
    /// Keeps `Gpu` from being `Sync`: `submit` uses the queue and command pool, which Vulkan
    /// requires callers to synchronise, and recording from two threads at once would race.
    _not_sync: PhantomData<Cell<()>>,
}

/// What [`Gpu::open_device`] made, before the shared part takes it over.
struct OpenedDevice {
    device: ash::Device,
    allocator: Allocator,
    physical: vk::PhysicalDevice,
    queue_family: u32,
    caps: Capabilities,
}

fn load_entry() -> Result<ash::Entry> {
    // SAFETY: loading the system Vulkan loader runs its initialisation; Tessera trusts the
    // installed loader, as every Vulkan program must.
    unsafe { ash::Entry::load() }.map_err(|e| GpuError::Loader(e.to_string()))
}

fn create_instance(
    entry: &ash::Entry,
    validation: bool,
    extra_extensions: &[&CStr],
) -> Result<ash::Instance> {
    let app_name = c"tessera";
    let app = vk::ApplicationInfo::default()
        .application_name(app_name)
        .engine_name(app_name)
        .api_version(vk::API_VERSION_1_3);
    let layers: Vec<*const i8> = if validation {
        // SAFETY: a plain query on a loaded entry.
        let available = unsafe { entry.enumerate_instance_layer_properties() }
            .call("vkEnumerateInstanceLayerProperties")?;
        let found = available
            .iter()
            .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
        if !found {
            return Err(GpuError::NoValidationLayer);
        }
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        vec![]
    };
    // SAFETY: a plain query on a loaded entry.
    let ext_props = unsafe { entry.enumerate_instance_extension_properties(None) }
        .call("vkEnumerateInstanceExtensionProperties")?;
    let mut extensions: Vec<*const i8> = extra_extensions.iter().map(|e| e.as_ptr()).collect();
    if has_extension(&ext_props, ash::ext::debug_utils::NAME) {
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    // With validation, synchronization validation too: a missing barrier is a race that the
    // other checks cannot see. The layer provides the extension that turns it on.
    let sync = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync);
    let mut with_sync = false;
    if validation {
        // SAFETY: a plain query on a loaded entry, for a layer that was found above.
        let layer_props =
            unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                .call("vkEnumerateInstanceExtensionProperties")?;
        if has_extension(&layer_props, ash::ext::validation_features::NAME) {
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
            with_sync = true;
        }
    }
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    if with_sync {
        info = info.push_next(&mut features);
    }
    // SAFETY: the create info and the layer and extension names it points at (static C
    // strings) outlive the call.
    unsafe { entry.create_instance(&info, None) }.call("vkCreateInstance")
}

fn device_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// Lists the devices without opening one, for `tessera info`.
pub fn list_devices() -> Result<Vec<DeviceListing>> {
    let entry = load_entry()?;
    let instance = create_instance(&entry, false, &[])?;
    // SAFETY: a plain query on the live instance created above.
    let physicals =
        unsafe { instance.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices");
    let result = physicals.map(|list| {
        list.iter()
            .enumerate()
            .map(|(index, &p)| {
                // SAFETY: `p` was enumerated from this live instance.
                let props = unsafe { instance.get_physical_device_properties(p) };
                DeviceListing {
                    index,
                    name: props
                        .device_name_as_c_str()
                        .map(|c| c.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                    device_type: format!("{:?}", props.device_type),
                }
            })
            .collect()
    });
    // SAFETY: nothing was created on the instance and nothing uses it after this.
    unsafe { instance.destroy_instance(None) };
    result
}

/// The device extensions Tessera enables whenever the device has them.
const OPTIONAL_EXTENSIONS: &[&CStr] = &[
    ash::ext::mesh_shader::NAME,
    ash::khr::acceleration_structure::NAME,
    ash::khr::ray_tracing_pipeline::NAME,
    ash::khr::ray_query::NAME,
    ash::khr::deferred_host_operations::NAME,
    ash::ext::shader_atomic_float::NAME,
    ash::ext::shader_image_atomic_int64::NAME,
    ash::nv::representative_fragment_test::NAME,
    ash::khr::fragment_shader_barycentric::NAME,
    ash::ext::fragment_shader_interlock::NAME,
    ash::khr::pipeline_executable_properties::NAME,
];

impl Gpu {
    pub fn new(options: &GpuOptions) -> Result<Gpu> {
        Self::with_instance_extensions(options, &[])
    }

    /// Opens the device with further instance extensions (a window system's surface ones);
    /// with any given, the device also enables `VK_KHR_swapchain` where it has it.
    pub fn with_instance_extensions(options: &GpuOptions, extra: &[&CStr]) -> Result<Gpu> {
        let entry = load_entry()?;
        let instance = create_instance(&entry, options.validation, extra)?;
        let validation = Arc::new(ValidationLog::default());
        // Until `DeviceShared` owns them, failures destroy the messenger and instance here.
        let messenger = if options.validation {
            match create_messenger(&entry, &instance, &validation) {
                Ok(m) => Some(m),
                Err(e) => {
                    // SAFETY: the instance was created above and nothing else owns or uses it.
                    unsafe { instance.destroy_instance(None) };
                    return Err(e);
                }
            }
        } else {
            None
        };
        let opened = match Self::open_device(&instance, options, !extra.is_empty()) {
            Ok(opened) => opened,
            Err(e) => {
                // SAFETY: `open_device` destroyed whatever it created on failure; the messenger
                // and instance were made above, are owned by nothing else, and the messenger
                // goes before the instance it belongs to.
                unsafe {
                    if let Some((debug, m)) = messenger {
                        debug.destroy_debug_utils_messenger(m, None);
                    }
                    instance.destroy_instance(None);
                }
                return Err(e);
            }
        };
        let acceleration = opened
            .caps
            .acceleration_structure
            .then(|| ash::khr::acceleration_structure::Device::new(&instance, &opened.device));
        let shared = Arc::new(DeviceShared {
            acceleration,
            device: opened.device,
            allocator: ManuallyDrop::new(Mutex::new(opened.allocator)),
            instance,
            messenger,
            validation,
            _entry: entry,
            open_submissions: AtomicU32::new(0),
            retired: Mutex::new(Vec::new()),
            hung: AtomicBool::new(false),
            timeout_ns: options.timeout.map_or(u64::MAX, |t| {
                u64::try_from(t.as_nanos()).unwrap_or(u64::MAX)
            }),
            pipeline_statistics: Mutex::new(Vec::new()),
            statistics_requested: options.pipeline_statistics,
        });
        let capture = options.pipeline_statistics && opened.caps.pipeline_executable_info;
        // From here on `shared` owns the device and instance: a failure drops it, which destroys
        // them exactly once.
        Self::finish(
            shared,
            opened.physical,
            opened.queue_family,
            opened.caps,
            capture,
        )
    }

    fn pick_physical(instance: &ash::Instance, index: Option<usize>) -> Result<vk::PhysicalDevice> {
        // SAFETY: a plain query on a live instance.
        let physicals =
            unsafe { instance.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices")?;
        if physicals.is_empty() {
            return Err(GpuError::NoDevice);
        }
        if let Some(index) = index {
            return physicals.get(index).copied().ok_or(GpuError::DeviceIndex {
                index,
                count: physicals.len(),
            });
        }
        let best = physicals
            .iter()
            .min_by_key(|&&p| {
                // SAFETY: `p` was enumerated from this live instance.
                device_rank(unsafe { instance.get_physical_device_properties(p) }.device_type)
            })
            .copied();
        best.ok_or(GpuError::NoDevice)
    }

    /// Picks the physical device and creates the logical device and its allocator. On failure
    /// it destroys what it created (the device), leaving the instance to the caller.
    fn open_device(
        instance: &ash::Instance,
        options: &GpuOptions,
        presenting: bool,
    ) -> Result<OpenedDevice> {
        let physical = Self::pick_physical(instance, options.device_index)?;
        // SAFETY: `physical` was enumerated from this live instance.
        let extensions = unsafe { instance.enumerate_device_extension_properties(physical) }
            .call("vkEnumerateDeviceExtensionProperties")?;
        let caps = caps::query(instance, physical, &extensions);
        if !has_extension(&extensions, ash::khr::push_descriptor::NAME) {
            return Err(GpuError::Unsupported {
                device: caps.device_name.clone(),
                what: "VK_KHR_push_descriptor".into(),
            });
        }
        // SAFETY: `physical` was enumerated from this live instance.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let queue_family = families
            .iter()
            .position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
                    && f.timestamp_valid_bits > 0
            })
            .ok_or_else(|| GpuError::Unsupported {
                device: caps.device_name.clone(),
                what: "a graphics+compute queue with timestamps".into(),
            })? as u32;

        let mut enabled: Vec<*const i8> = vec![ash::khr::push_descriptor::NAME.as_ptr()];
        for ext in OPTIONAL_EXTENSIONS {
            if has_extension(&extensions, ext) {
                enabled.push(ext.as_ptr());
            }
        }
        if presenting && has_extension(&extensions, ash::khr::swapchain::NAME) {
            enabled.push(ash::khr::swapchain::NAME.as_ptr());
        }
        let device = Self::create_device(instance, physical, queue_family, &caps, &enabled)?;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: true,
            allocation_sizes: Default::default(),
        });
        match allocator {
            Ok(allocator) => Ok(OpenedDevice {
                device,
                allocator,
                physical,
                queue_family,
                caps,
            }),
            Err(e) => {
                // SAFETY: the device was just created and nothing has been made on it.
                unsafe { device.destroy_device(None) };
                Err(GpuError::Allocation {
                    name: "allocator".into(),
                    bytes: 0,
                    message: e.to_string(),
                })
            }
        }
    }

    /// Makes what `Gpu` itself owns (command pool, samplers) on the shared device.
    fn finish(
        shared: Arc<DeviceShared>,
        physical: vk::PhysicalDevice,
        queue_family: u32,
        caps: Capabilities,
        capture_statistics: bool,
    ) -> Result<Gpu> {
        let device = shared.device.clone();
        let instance = &shared.instance;
        // SAFETY: the device was created with one queue in `queue_family`.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let debug_device = shared
            .messenger
            .as_ref()
            .map(|_| ash::ext::debug_utils::Device::new(instance, &device));
        let mesh_shader = caps
            .mesh_shader
            .then(|| ash::ext::mesh_shader::Device::new(instance, &device));
        // Null handles until created: if a creation below fails, dropping `gpu` destroys the
        // ones made so far (destroying a null handle does nothing).
        let pipeline_executables = capture_statistics
            .then(|| ash::khr::pipeline_executable_properties::Device::new(instance, &device));
        let ray_tracing = (caps.ray_tracing_pipeline && caps.acceleration_structure)
            .then(|| ash::khr::ray_tracing_pipeline::Device::new(instance, &device));
        let mut gpu = Gpu {
            ray_tracing,
            push_descriptor: ash::khr::push_descriptor::Device::new(instance, &device),
            mesh_shader,
            pipeline_executables,
            debug_device,
            device,
            queue,
            queue_family,
            command_pool: vk::CommandPool::null(),
            sampler_nearest: vk::Sampler::null(),
            sampler_linear: vk::Sampler::null(),
            caps,
            physical,
            shared,
            _not_sync: PhantomData,
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: the create info is valid and names the device's queue family.
        gpu.command_pool = unsafe { gpu.device.create_command_pool(&pool_info, None) }
            .call("vkCreateCommandPool")?;
        let sampler = |filter: vk::Filter| {
            let info = vk::SamplerCreateInfo::default()
                .mag_filter(filter)
                .min_filter(filter)
                .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE);
            // SAFETY: the create info is valid and fully initialised.
            unsafe { gpu.device.create_sampler(&info, None) }.call("vkCreateSampler")
        };
        let nearest = sampler(vk::Filter::NEAREST)?;
        gpu.sampler_nearest = nearest;
        let linear = sampler(vk::Filter::LINEAR)?;
        gpu.sampler_linear = linear;
        Ok(gpu)
    }

    pub fn caps(&self) -> &Capabilities {
        &self.caps
    }

    /// Validation-layer errors seen so far (empty when validation is off).
    pub fn validation_errors(&self) -> Vec<String> {
        self.shared.validation.errors()
    }

    /// The log the validation callback writes to. It outlives this handle: messages raised
    /// while the last objects are dropped (and the device with them) still land in it.
    pub fn validation_log(&self) -> Arc<ValidationLog> {
        self.shared.validation.clone()
    }

    pub fn validation_enabled(&self) -> bool {
        self.shared.messenger.is_some()
    }

    pub fn device(&self) -> &ash::Device {
        &self.device
    }

    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical
    }

    /// Names a Vulkan object for the validation layer and capture tools.
    /// Fills `next` (a properties structure of an extension) from the physical device.
    pub(crate) fn chained_properties<T: vk::ExtendsPhysicalDeviceProperties2>(&self, next: &mut T) {
        let mut properties = vk::PhysicalDeviceProperties2::default().push_next(next);
        // SAFETY: a plain query on a live physical device of this instance; `next` outlives it.
        unsafe {
            self.shared
                .instance
                .get_physical_device_properties2(self.physical, &mut properties)
        };
    }

    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        if let (Some(debug), Ok(name)) = (&self.debug_device, CString::new(name)) {
            let info = vk::DebugUtilsObjectNameInfoEXT::default()
                .object_handle(handle)
                .object_name(&name);
            // Naming is a debugging aid; failing to name must not fail the work.
            // SAFETY: `handle` is an object of this device and `name` outlives the call.
            let _ = unsafe { debug.set_debug_utils_object_name(&info) };
        }
    }

    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: the queue, which this call synchronises on, is used only by `submit` on this
        // same thread (`Gpu` is not `Sync`).
        unsafe { self.device.device_wait_idle() }.call("vkDeviceWaitIdle")
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: the command pool and samplers were created on this device and only `Gpu`
        // hands them out (command buffers live within one `submit`, samplers are bound only in
        // recordings that `submit` waits for); waiting for idle makes sure nothing uses them.
        // The device itself stays alive in `shared` as long as any object needs it.
        if self.shared.hung.load(std::sync::atomic::Ordering::Acquire) {
            return; // see `DeviceShared::hung`
        }
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_sampler(self.sampler_nearest, None);
            self.device.destroy_sampler(self.sampler_linear, None);
        }
    }
}
