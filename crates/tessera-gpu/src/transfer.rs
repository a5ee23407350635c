//! Transfer and layout commands: buffer copies, fills and small updates, image layout moves,
//! and copies between buffers and images.

use crate::commands::Recorder;
use crate::memory::{aspect_of, full_range, Buffer, Image};
use ash::vk;

impl Recorder<'_> {
    pub fn copy_buffer(&self, src: &Buffer, dst: &Buffer, bytes: u64) {
        let region = [vk::BufferCopy::default().size(bytes)];
        // SAFETY: `self.cmd` is recording (see `record_and_run`) and both buffers are live
        // objects of this device; `submit` waits for the copy before it returns.
        unsafe {
            self.gpu
                .device
                .cmd_copy_buffer(self.cmd, src.handle, dst.handle, &region)
        };
    }

    /// Copies each `(src_offset, dst_offset, bytes)` region from `src` to `dst` in one command
    /// (rows of an image into a wider one, say).
    pub fn copy_buffer_regions(&self, src: &Buffer, dst: &Buffer, regions: &[(u64, u64, u64)]) {
        let regions: Vec<vk::BufferCopy> = regions
            .iter()
            .map(|&(src_offset, dst_offset, size)| vk::BufferCopy {
                src_offset,
                dst_offset,
                size,
            })
            .collect();
        if regions.is_empty() {
            return;
        }
        // SAFETY: as for `copy_buffer`; the caller keeps every region inside both buffers
        // (`Target::record_side_by_side` checks its sizes).
        unsafe {
            self.gpu
                .device
                .cmd_copy_buffer(self.cmd, src.handle, dst.handle, &regions)
        };
    }

    /// Copies `bytes` from `src` at `src_offset` to `dst` at `dst_offset`.
    pub fn copy_buffer_range(
        &self,
        src: &Buffer,
        src_offset: u64,
        dst: &Buffer,
        dst_offset: u64,
        bytes: u64,
    ) {
        let region = [vk::BufferCopy::default()
            .src_offset(src_offset)
            .dst_offset(dst_offset)
            .size(bytes)];
        // SAFETY: as for `copy_buffer`; the caller keeps both ranges inside their buffers
        // (`Readback::record_copy` checks its own).
        unsafe {
            self.gpu
                .device
                .cmd_copy_buffer(self.cmd, src.handle, dst.handle, &region)
        };
    }

    /// Writes `data` (a multiple of 4 bytes, at most 65,536) to the start of `dst` in the
    /// command stream, for small per-frame values that must not need a staging buffer.
    pub fn update_buffer(&self, dst: &Buffer, data: &[u8]) {
        assert!(
            data.len().is_multiple_of(4) && data.len() <= 65536 && data.len() as u64 <= dst.size,
            "update of {} bytes into '{}' ({} bytes)",
            data.len(),
            dst.name,
            dst.size
        );
        // SAFETY: `self.cmd` is recording and `dst` is a live buffer of this device, created
        // with TRANSFER_DST usage by the caller; the size rules were checked above.
        unsafe {
            self.gpu
                .device
                .cmd_update_buffer(self.cmd, dst.handle, 0, data)
        };
    }

    pub fn fill_buffer(&self, dst: &Buffer, value: u32) {
        // SAFETY: `self.cmd` is recording and `dst` is a live buffer of this device; the fill
        // covers the whole buffer.
        unsafe {
            self.gpu
                .device
                .cmd_fill_buffer(self.cmd, dst.handle, 0, vk::WHOLE_SIZE, value)
        };
    }

    fn image_barrier(&self, image: &Image, from: vk::ImageLayout, to: vk::ImageLayout) {
        self.layout_barrier(
            image.handle,
            full_range(image.format, image.layers),
            from,
            to,
        );
    }

    /// Moves `range` of `image` from layout `from` to `to`, after all earlier writes and
    /// before all later accesses.
    pub(crate) fn layout_barrier(
        &self,
        image: vk::Image,
        range: vk::ImageSubresourceRange,
        from: vk::ImageLayout,
        to: vk::ImageLayout,
    ) {
        let barrier = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE)
            .old_layout(from)
            .new_layout(to)
            .image(image)
            .subresource_range(range)];
        let dep = vk::DependencyInfo::default().image_memory_barriers(&barrier);
        // SAFETY: `self.cmd` is recording; the caller names a live image of this device and a
        // range within it.
        unsafe { self.gpu.device.cmd_pipeline_barrier2(self.cmd, &dep) };
    }

    /// Moves an image into `GENERAL` layout for storage or attachment use; its old contents go.
    pub fn discard_to_general(&self, image: &Image) {
        self.image_barrier(image, vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL);
    }

    /// Copies tightly packed texels into the whole image and leaves it ready for sampling.
    pub fn copy_buffer_to_image(&self, src: &Buffer, dst: &Image) {
        self.image_barrier(
            dst,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
        let region = [vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_extent(dst.extent)];
        // SAFETY: `self.cmd` is recording; `dst` was moved to `TRANSFER_DST_OPTIMAL` just above and
        // `src` is a live buffer of this device.
        unsafe {
            self.gpu.device.cmd_copy_buffer_to_image(
                self.cmd,
                src.handle,
                dst.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &region,
            )
        };
        self.image_barrier(
            dst,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        );
    }

    /// Copies a 2-D image in `GENERAL` layout into a buffer, tightly packed, layer after layer.
    pub fn copy_image_to_buffer(&self, src: &Image, dst: &Buffer) {
        self.copy_layers_to_buffer(src, 0..src.layers, dst);
    }

    /// Copies one layer of a layered 2-D image in `GENERAL` layout into a buffer.
    pub fn copy_image_layer_to_buffer(&self, src: &Image, layer: u32, dst: &Buffer) {
        assert!(
            layer < src.layers,
            "layer {layer} of {} ('{}')",
            src.layers,
            src.name
        );
        self.copy_layers_to_buffer(src, layer..layer + 1, dst);
    }

    fn copy_layers_to_buffer(&self, src: &Image, layers: std::ops::Range<u32>, dst: &Buffer) {
        let region = [vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: aspect_of(src.format),
                mip_level: 0,
                base_array_layer: layers.start,
                layer_count: layers.len() as u32,
            })
            .image_extent(src.extent)];
        // SAFETY: `self.cmd` is recording; `src` is a live image the caller left in `GENERAL`
        // layout and `dst` a live buffer of this device.
        unsafe {
            self.gpu.device.cmd_copy_image_to_buffer(
                self.cmd,
                src.handle,
                vk::ImageLayout::GENERAL,
                dst.handle,
                &region,
            )
        };
    }
}
