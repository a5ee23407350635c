//! What every GPU object needs to outlive it: the device, its allocator and the instance.
//! [`crate::Gpu`] and each [`crate::Buffer`], [`crate::Image`], [`crate::Pipeline`] and
//! [`crate::Timer`] hold an `Arc` of it, so the device goes away only after the last of them.

use crate::context::ValidationLog;
use ash::vk;
use gpu_allocator::vulkan::{Allocation, Allocator};
use std::mem::ManuallyDrop;
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
}

impl DeviceShared {
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
        // SAFETY: this is the last reference to the device: every object created on it holds
        // an `Arc` of this struct, so all of them are gone and none of their handles is used
        // again. Waiting for idle first means no submitted work still runs. The allocator is
        // dropped before the device it allocated from, the device before the instance, and the
        // messenger (whose callback reads `validation`, still alive here) before the instance.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((debug, m)) = self.messenger.take() {
                debug.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
