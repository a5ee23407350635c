//! The Khronos validation layer's messages: a log of errors and warnings, and the debug
//! messenger whose callback fills it.

use crate::error::{Result, VkContext};
use crate::shared::Messenger;
use ash::vk;
use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

pub(crate) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Validation messages, shared with the debug callback.
#[derive(Default)]
pub struct ValidationLog {
    errors: Mutex<Vec<String>>,
    warnings: Mutex<Vec<String>>,
}

impl ValidationLog {
    pub fn errors(&self) -> Vec<String> {
        self.errors.lock().map(|e| e.clone()).unwrap_or_default()
    }
    pub fn warnings(&self) -> Vec<String> {
        self.warnings.lock().map(|e| e.clone()).unwrap_or_default()
    }
}

/// Called by the validation layer for each message.
///
/// # Safety
/// `data` must be null or valid callback data for the duration of the call, and `user` null or
/// the `ValidationLog` the messenger was created with, alive until the messenger is destroyed
/// (`create_messenger` and `DeviceShared` see to both).
// SAFETY: only the loader calls it, with the arguments the Vulkan spec promises (see above).
unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user.is_null() {
        return vk::FALSE;
    }
    // SAFETY: `user` is the `ValidationLog` the messenger was created with
    // (`create_messenger`); `DeviceShared` keeps it alive until the messenger is destroyed.
    let log = unsafe { &*(user as *const ValidationLog) };
    // SAFETY: the loader passes callback data valid for the duration of the call (checked
    // non-null above) whose message is a NUL-terminated string.
    let message = unsafe { (*data).message_as_c_str() }
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        eprintln!("[vulkan validation error] {message}");
        if let Ok(mut e) = log.errors.lock() {
            e.push(message);
        }
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        if let Ok(mut w) = log.warnings.lock() {
            w.push(message);
        }
    }
    vk::FALSE
}

/// A debug messenger that records validation errors and warnings into `validation`.
pub(crate) fn create_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
    validation: &Arc<ValidationLog>,
) -> Result<Messenger> {
    let debug = ash::ext::debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE
                | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
        )
        .pfn_user_callback(Some(debug_callback))
        .user_data(Arc::as_ptr(validation) as *mut c_void);
    // SAFETY: the create info is valid; its user data points into `validation`, which the
    // caller keeps alive (in `DeviceShared`) until after the messenger is destroyed.
    let m = unsafe { debug.create_debug_utils_messenger(&info, None) }
        .call("vkCreateDebugUtilsMessengerEXT")?;
    Ok((debug, m))
}
