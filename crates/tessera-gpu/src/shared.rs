//! What every GPU object needs to outlive it: the device, its allocator and the instance.
//! [`crate::Gpu`] and each [`crate::Buffer`], [`crate::Image`], [`crate::Pipeline`] and
//! [`crate::Timer`] hold an `Arc` of it, so the device goes away only after the last of them.
//!
//! Objects dropped while a submission is being recorded or runs (say, a buffer made and dropped
//! inside a [`crate::Gpu::submit`] closure) are not destroyed at once: the command buffer may
//! still name them. They are kept as [`Retired`] handles and destroyed once the submission's
//! fence has signalled.

use crate::validation::ValidationLog;
use ash::vk;
use gpu_allocator::vulkan::{Allocation, Allocator};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

pub(crate) type Messenger = (ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT);

pub(crate) struct DeviceShared {
    pub(crate) device: ash::Device,
    /// Dropped by hand in `Drop`, before the device it allocates from.
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    pub(crate) instance: ash::Instance,
    pub(crate) messenger: Option<Messenger>,
    /// What the messenger's callback points at; must outlive the messenger.
    pub(crate) validation: Arc<ValidationLog>,
    pub(crate) _entry: ash::Entry,
    /// Submissions being recorded or waited for.
    pub(crate) open_submissions: AtomicU32,
    /// Objects dropped while a submission was open, destroyed when the last one closes.
    pub(crate) retired: Mutex<Vec<Retired>>,
    /// Set when a submission outran its time limit: its work may still run (an endless loop
    /// in a shader), so nothing it might use is destroyed, the device included; the process
    /// is expected to end soon, and the handles end with it.
    pub(crate) hung: AtomicBool,
    /// How long a submission's fence is waited for ([`crate::GpuOptions::timeout`]).
    pub(crate) timeout_ns: u64,
    /// What the driver reported of each pipeline created with statistics captured.
    pub(crate) pipeline_statistics: Mutex<Vec<crate::statistics::PipelineStatistics>>,
    /// [`crate::GpuOptions::pipeline_statistics`].
    pub(crate) statistics_requested: bool,
    /// The acceleration-structure functions, where the device has them (a dropped structure
    /// needs them to be destroyed).
    pub(crate) acceleration: Option<ash::khr::acceleration_structure::Device>,
}

/// The Vulkan handles (and memory) of a dropped GPU object, destroyed in the order given.
pub(crate) enum Retired {
    Buffer(vk::Buffer, Option<Allocation>),
    Image {
        view: vk::ImageView,
        image: vk::Image,
        allocation: Option<Allocation>,
    },
    Pipeline {
        pipeline: vk::Pipeline,
        layout: vk::PipelineLayout,
        set_layout: vk::DescriptorSetLayout,
    },
    QueryPool(vk::QueryPool),
    AccelerationStructure(vk::AccelerationStructureKHR),
}

/// Keeps a submission open while it lives: objects dropped meanwhile wait for it.
pub(crate) struct OpenSubmission<'a>(&'a DeviceShared);

impl Drop for OpenSubmission<'_> {
    fn drop(&mut self) {
        if self.0.hung.load(Ordering::Acquire) {
            return; // the submission stays open for good: everything retired is kept
        }
        if self.0.open_submissions.fetch_sub(1, Ordering::AcqRel) == 1 {
            let retired = match self.0.retired.lock() {
                Ok(mut list) => std::mem::take(&mut *list),
                Err(poisoned) => std::mem::take(&mut *poisoned.into_inner()),
            };
            for object in retired {
                // SAFETY: the submission that might have used it has completed (its fence was
                // waited for) or was never submitted, and no other submission is open.
                unsafe { self.0.release_handles(object) };
            }
        }
    }
}

impl DeviceShared {
    /// Marks a submission open until the returned guard is dropped (after its fence wait).
    pub(crate) fn open_submission(&self) -> OpenSubmission<'_> {
        self.open_submissions.fetch_add(1, Ordering::AcqRel);
        OpenSubmission(self)
    }

    /// Destroys a dropped object's handles now, or once the open submissions are done.
    pub(crate) fn retire(&self, object: Retired) {
        if self.open_submissions.load(Ordering::Acquire) > 0 {
            match self.retired.lock() {
                Ok(mut list) => return list.push(object),
                Err(poisoned) => return poisoned.into_inner().push(object),
            }
        }
        // SAFETY: no submission is open, and every submission waits for its fence before it
        // closes, so no work on the GPU uses the object.
        unsafe { self.release_handles(object) }
    }

    /// # Safety
    /// The handles were created on this device and no pending or recording command buffer
    /// uses them.
    unsafe fn release_handles(&self, object: Retired) {
        let device = &self.device;
        // SAFETY: the caller's promise; each object goes before what it was made from (view
        // before image, pipeline before its layouts, resource before its memory). Null handles
        // of half-made objects are ignored by Vulkan.
        unsafe {
            match object {
                Retired::Buffer(buffer, allocation) => {
                    device.destroy_buffer(buffer, None);
                    if let Some(a) = allocation {
                        self.free(a);
                    }
                }
                Retired::Image {
                    view,
                    image,
                    allocation,
                } => {
                    device.destroy_image_view(view, None);
                    device.destroy_image(image, None);
                    if let Some(a) = allocation {
                        self.free(a);
                    }
                }
                Retired::Pipeline {
                    pipeline,
                    layout,
                    set_layout,
                } => {
                    device.destroy_pipeline(pipeline, None);
                    device.destroy_pipeline_layout(layout, None);
                    device.destroy_descriptor_set_layout(set_layout, None);
                }
                Retired::QueryPool(pool) => device.destroy_query_pool(pool, None),
                Retired::AccelerationStructure(structure) => {
                    // Only made through `acceleration`, so it is present.
                    if let Some(acceleration) = &self.acceleration {
                        acceleration.destroy_acceleration_structure(structure, None);
                    }
                }
            }
        }
    }

    /// Gives an allocation back to the allocator. Called from `Drop` impls, so it never panics:
    /// with a poisoned lock the allocation is left to the allocator's own teardown, which frees
    /// every memory block it holds.
    pub(crate) fn free(&self, allocation: Allocation) {
        match self.allocator.lock() {
            Ok(mut allocator) => {
                if let Err(e) = allocator.free(allocation) {
                    log::warn!("freeing an allocation failed: {e}");
                }
            }
            Err(_) => log::warn!("allocator lock poisoned; allocation left to the allocator"),
        }
    }
}

impl Drop for DeviceShared {
    fn drop(&mut self) {
        if self.hung.load(Ordering::Acquire) {
            // Waiting for idle would wait for the hung work; destroying would pull memory
            // from under it. The allocator's memory is left to the process's end.
            return;
        }
        // SAFETY: this is the last reference to the device: every object created on it holds
        // an `Arc` of this struct, so all of them are gone and none of their handles is used
        // again. Waiting for idle first means no submitted work still runs. The allocator is
        // dropped before the device it allocated from, the device before the instance, and the
        // messenger (whose callback reads `validation`, still alive here) before the instance.
        unsafe {
            let _ = self.device.device_wait_idle();
            let retired = match self.retired.get_mut() {
                Ok(list) => std::mem::take(list),
                Err(poisoned) => std::mem::take(poisoned.into_inner()),
            };
            for object in retired {
                self.release_handles(object);
            }
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((debug, m)) = self.messenger.take() {
                debug.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
