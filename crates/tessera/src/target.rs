//! Frames that compute passes write: one packed RGBA8 `u32` per pixel in a storage buffer.

use crate::error::Result;
use tessera_data::RgbaImage;
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation};

/// Where a frame's pixels go: packed RGBA8, one `u32` per pixel.
pub struct Target {
    pub pixels: Buffer,
    pub width: u32,
    pub height: u32,
}

impl Target {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<Target> {
        crate::error::check_image_size(width, height)?;
        let pixels = gpu.create_buffer(
            "pixels",
            width as u64 * height as u64 * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(Target {
            pixels,
            width,
            height,
        })
    }

    /// Fills every pixel with `value`, so a pixel the shader never writes is caught.
    pub fn poison(&self, gpu: &Gpu, value: u32) -> Result<()> {
        gpu.submit("poison pixels", |rec| rec.fill_buffer(&self.pixels, value))?;
        Ok(())
    }

    pub fn read(&self, gpu: &Gpu) -> Result<RgbaImage> {
        let bytes = gpu.read_buffer(&self.pixels)?;
        Ok(RgbaImage {
            width: self.width,
            height: self.height,
            pixels: bytemuck::allocation::pod_collect_to_vec(
                &bytes[..(self.width * self.height * 4) as usize],
            ),
        })
    }
}
