use ash::vk;
use std::path::PathBuf;

/// Everything that can go wrong below the techniques. Each variant names the call, resource or
/// file involved so that a message read by a user points at the cause.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("the Vulkan loader could not be opened ({0}); install libvulkan1, and mesa-vulkan-drivers for a CPU device")]
    Loader(String),
    #[error("{call} failed: {result}")]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },
    /// `VK_ERROR_SURFACE_LOST_KHR`: the window went away (closed by a person or the window
    /// system) while its swapchain was in use; a viewer ends rather than fails.
    #[error("{call} failed: the window's surface is gone (the window was closed)")]
    SurfaceLost { call: &'static str },
    #[error("no Vulkan device found; install a GPU driver or mesa-vulkan-drivers (lavapipe)")]
    NoDevice,
    #[error("device index {index} does not exist: {count} device(s) found (see `tessera info`)")]
    DeviceIndex { index: usize, count: usize },
    #[error("device '{device}' lacks {what}, which this needs")]
    Unsupported { device: String, what: String },
    #[error("the Khronos validation layer was requested but is not installed (Debian: vulkan-validationlayers)")]
    NoValidationLayer,
    #[error("allocating {bytes} bytes for '{name}' failed: {message}")]
    Allocation {
        name: String,
        bytes: u64,
        message: String,
    },
    #[error("'{name}' needs {bytes} bytes but the device offers at most {limit} bytes ({what})")]
    TooLarge {
        name: String,
        bytes: u64,
        limit: u64,
        what: &'static str,
    },
    #[error(
        "'{name}' is {extent} texels along an axis but the device's 3-D images hold at most {limit} texels per axis"
    )]
    ImageTooLarge {
        name: String,
        extent: u32,
        limit: u32,
    },
    #[error(
        "timer scopes {scopes} have no results: the frame that recorded them was never submitted"
    )]
    TimerNotSubmitted { scopes: String },
    #[error("device lost during '{pass}'")]
    DeviceLost { pass: String },
    #[error(
        "'{pass}' did not finish within {seconds} s (the GPU time limit): a shader that does not end, or work too large for this device; the device is left as it is"
    )]
    Timeout { pass: String, seconds: f64 },
    #[error("'{pass}' was not started: earlier work on this device did not finish in time")]
    Hung { pass: String },
    #[error("shader {path}: {log}")]
    ShaderCompile { path: String, log: String },
    #[error("shader {path}: {message}")]
    ShaderReflect { path: String, message: String },
    /// A request the device could serve but whose arguments make no sense (an empty list).
    #[error("{0}")]
    Invalid(String),
    #[error("shader cache {path}: {source}")]
    ShaderCache {
        path: PathBuf,
        source: std::io::Error,
    },
}

pub type Result<T> = std::result::Result<T, GpuError>;

/// Attaches the Vulkan call name to a raw result, since `vk::Result` alone does not say which of
/// dozens of calls in a frame failed.
pub(crate) trait VkContext<T> {
    fn call(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn call(self, call: &'static str) -> Result<T> {
        self.map_err(|result| GpuError::of_call(call, result))
    }
}

impl GpuError {
    /// The error of Vulkan call `call` that returned `result`.
    pub fn of_call(call: &'static str, result: vk::Result) -> GpuError {
        match result {
            vk::Result::ERROR_SURFACE_LOST_KHR => GpuError::SurfaceLost { call },
            result => GpuError::Vulkan { call, result },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_extent_limit_speaks_of_texels() {
        let e = GpuError::ImageTooLarge {
            name: "volume".into(),
            extent: 5000,
            limit: 2048,
        };
        let text = e.to_string();
        assert!(text.contains("5000 texels") && text.contains("2048 texels per axis"));
        assert!(!text.contains("bytes"), "{text}");
    }

    #[test]
    fn a_lost_surface_is_told_apart_from_other_failures() {
        let lost: Result<()> = Err(vk::Result::ERROR_SURFACE_LOST_KHR).call("vkQueuePresentKHR");
        assert!(matches!(
            lost,
            Err(GpuError::SurfaceLost {
                call: "vkQueuePresentKHR"
            })
        ));
        assert!(lost.unwrap_err().to_string().contains("window was closed"));
        let other: Result<()> = Err(vk::Result::ERROR_DEVICE_LOST).call("vkQueueSubmit");
        assert!(matches!(other, Err(GpuError::Vulkan { .. })));
    }
}
