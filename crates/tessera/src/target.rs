//! Frames that compute passes write: one packed RGBA8 `u32` per pixel in a storage buffer.

use crate::error::Result;
use tessera_data::RgbaImage;
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation, Recorder};

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

    /// Records `left` and `right` (of this target's height, their widths summing to its)
    /// copied side by side into this target, row by row, as [`RgbaImage::side_by_side`] puts
    /// two images: a stereo pair shown as one image without a read back.
    pub fn record_side_by_side(&self, rec: &Recorder, left: &Target, right: &Target) -> Result<()> {
        if left.height != self.height
            || right.height != self.height
            || left.width + right.width != self.width
        {
            return Err(crate::error::Error::Invalid(format!(
                "side by side: {}x{} and {}x{} into {}x{}",
                left.width, left.height, right.width, right.height, self.width, self.height
            )));
        }
        rec.barrier();
        let row = u64::from(self.width) * 4;
        for (part, at) in [(left, 0), (right, u64::from(left.width) * 4)] {
            let bytes = u64::from(part.width) * 4;
            let rows: Vec<(u64, u64, u64)> = (0..u64::from(self.height))
                .map(|y| (y * bytes, y * row + at, bytes))
                .collect();
            rec.copy_buffer_regions(&part.pixels, &self.pixels, &rows);
        }
        rec.barrier();
        Ok(())
    }

    pub fn read(&self, gpu: &Gpu) -> Result<RgbaImage> {
        let count = self.width as usize * self.height as usize;
        Ok(RgbaImage {
            width: self.width,
            height: self.height,
            pixels: gpu.read_elements(&self.pixels, count)?,
        })
    }
}
