//! What the tessera-gpu integration tests share: the device they run on and the check that
//! the validation layer reported nothing.

use tessera_gpu::{Buffer, Gpu, GpuOptions, MemoryLocation};

/// The default device with validation, or `None` (after saying so) where none opens.
pub fn open() -> Option<Gpu> {
    match Gpu::new(&GpuOptions {
        device_index: None,
        validation: true,
        ..GpuOptions::default()
    }) {
        Ok(gpu) => Some(gpu),
        Err(e) => {
            tessera_test::skip("", &format!("no Vulkan device ({e})"));
            None
        }
    }
}

/// Fails the test on any error the validation layer reported so far.
#[allow(dead_code)] // not every test file checks through it
pub fn assert_clean(gpu: &Gpu) {
    let errors = gpu.validation_errors();
    assert!(errors.is_empty(), "{errors:?}");
}

/// A 64 KiB device buffer for frames that fill it (work to time).
#[allow(dead_code)] // not every test file times frames
pub fn fill_target(gpu: &Gpu) -> Buffer {
    gpu.create_buffer(
        "frame work",
        1 << 16,
        tessera_gpu::vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
    .unwrap()
}
