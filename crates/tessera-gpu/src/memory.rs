//! Buffers and images with their allocations, plus staging upload and readback.

use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use crate::shared::{DeviceShared, Retired};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// A buffer with its memory. Dropping it destroys the buffer and frees the memory; it keeps the
/// device alive meanwhile, so it may outlive the [`Gpu`] that made it.
///
/// Dropping is always safe: every [`Gpu::submit`] waits for its fence before it returns, and a
/// buffer dropped while a submission is recorded or runs is destroyed only after that
/// submission completes (`shared.rs`).
pub struct Buffer {
    pub handle: vk::Buffer,
    pub size: u64,
    pub name: String,
    allocation: Option<Allocation>,
    shared: Arc<DeviceShared>,
}

impl Buffer {
    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.as_ref()?.mapped_slice()
    }
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        self.allocation.as_mut()?.mapped_slice_mut()
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        self.shared
            .retire(Retired::Buffer(self.handle, self.allocation.take()));
    }
}

/// An image with its view and memory; like [`Buffer`], it frees itself when dropped and keeps
/// the device alive meanwhile.
pub struct Image {
    pub handle: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent3D,
    /// Array layers of a 2-D image (one per view when rendering with multiview).
    pub layers: u32,
    pub name: String,
    allocation: Option<Allocation>,
    shared: Arc<DeviceShared>,
}

impl Drop for Image {
    fn drop(&mut self) {
        self.shared.retire(Retired::Image {
            view: self.view,
            image: self.handle,
            allocation: self.allocation.take(),
        });
    }
}

fn allocation_error(name: &str, bytes: u64, e: gpu_allocator::AllocationError) -> GpuError {
    GpuError::Allocation {
        name: name.to_string(),
        bytes,
        message: e.to_string(),
    }
}

impl Gpu {
    /// Refuses sizes the device cannot hold before asking the driver, so the user gets a message
    /// with the numbers instead of an out-of-memory code.
    pub fn check_fits(&self, name: &str, bytes: u64) -> Result<()> {
        let limit = self.caps().device_local_bytes;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                name: name.to_string(),
                bytes,
                limit,
                what: "device-local memory",
            });
        }
        Ok(())
    }

    pub fn create_buffer(
        &self,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Buffer> {
        let size = size.max(4);
        if location == MemoryLocation::GpuOnly {
            self.check_fits(name, size)?;
        }
        // Buffers are bound whole: one past the range would be bound out of bounds.
        let range = self.caps().max_storage_buffer_range;
        if usage.contains(vk::BufferUsageFlags::STORAGE_BUFFER) && size > range {
            return Err(GpuError::TooLarge {
                name: name.to_string(),
                bytes: size,
                limit: range,
                what: "its largest storage buffer",
            });
        }
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: the create info is valid (non-zero size, exclusive sharing).
        let handle = unsafe { self.device.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        // From here on dropping `buffer` destroys what has been made so far.
        let mut buffer = Buffer {
            handle,
            size,
            name: name.to_string(),
            allocation: None,
            shared: self.shared.clone(),
        };
        // SAFETY: `handle` is a live buffer of this device.
        let requirements = unsafe { self.device.get_buffer_memory_requirements(handle) };
        let allocation = self
            .shared
            .allocator
            .lock()
            .map_err(|_| GpuError::Allocation {
                name: name.into(),
                bytes: size,
                message: "allocator lock poisoned".into(),
            })?
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| allocation_error(name, size, e))?;
        // SAFETY: this allocation backs only this buffer, and `Drop` destroys the buffer before
        // it frees the allocation, as `memory` requires.
        let (memory, offset) = (unsafe { allocation.memory() }, allocation.offset());
        buffer.allocation = Some(allocation);
        // SAFETY: the allocation was made for this buffer's requirements, at a suitably
        // aligned offset, and the buffer has no memory bound yet.
        unsafe { self.device.bind_buffer_memory(handle, memory, offset) }
            .call("vkBindBufferMemory")?;
        self.set_name(handle, name);
        Ok(buffer)
    }

    /// A device-local buffer filled with `data` through a staging copy.
    pub fn upload_buffer(
        &self,
        name: &str,
        data: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Buffer> {
        let buffer = self.create_buffer(
            name,
            data.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let staging = self.staging_with(name, data)?;
        self.submit(&format!("upload {name}"), |cmd| {
            cmd.copy_buffer(&staging, &buffer, data.len() as u64);
        })?;
        Ok(buffer)
    }

    /// A host-visible copy source holding `data`, for uploads recorded by the caller (e.g. a
    /// new time step each frame).
    pub fn staging_with(&self, name: &str, data: &[u8]) -> Result<Buffer> {
        let mut staging = self.create_buffer(
            &format!("{name} (staging)"),
            data.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        match staging.mapped_mut() {
            Some(bytes) => bytes[..data.len()].copy_from_slice(data),
            None => {
                return Err(GpuError::Allocation {
                    name: name.into(),
                    bytes: data.len() as u64,
                    message: "staging memory is not host-visible".into(),
                });
            }
        }
        Ok(staging)
    }

    /// Copies a buffer back to the host.
    pub fn read_buffer(&self, buffer: &Buffer) -> Result<Vec<u8>> {
        self.read_buffer_bytes(buffer, buffer.size)
    }

    /// The whole of `buffer` as elements of `T` (a trailing part of an element is dropped).
    pub fn read_buffer_as<T: bytemuck::Pod>(&self, buffer: &Buffer) -> Result<Vec<T>> {
        let count = buffer.size as usize / std::mem::size_of::<T>().max(1);
        self.read_elements(buffer, count)
    }

    /// The first `count` elements of `T` in `buffer`; only their bytes are copied back. A
    /// buffer shorter than that is an error naming it.
    pub fn read_elements<T: bytemuck::Pod>(&self, buffer: &Buffer, count: usize) -> Result<Vec<T>> {
        let bytes = (count as u64).saturating_mul(std::mem::size_of::<T>() as u64);
        if bytes > buffer.size {
            return Err(GpuError::Invalid(format!(
                "reading {count} elements of {} bytes from '{}', which holds {} bytes",
                std::mem::size_of::<T>(),
                buffer.name,
                buffer.size
            )));
        }
        let data = self.read_buffer_bytes(buffer, bytes)?;
        Ok(bytemuck::allocation::pod_collect_to_vec(&data))
    }

    /// The first `bytes` bytes of `buffer` (at most its size).
    fn read_buffer_bytes(&self, buffer: &Buffer, bytes: u64) -> Result<Vec<u8>> {
        if bytes == 0 {
            return Ok(Vec::new());
        }
        let staging = self.create_buffer(
            &format!("{} (readback)", buffer.name),
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.submit(&format!("read back {}", buffer.name), |cmd| {
            cmd.copy_buffer(buffer, &staging, bytes);
        })?;
        match staging.mapped() {
            Some(mapped) => Ok(mapped[..bytes as usize].to_vec()),
            None => Err(GpuError::Allocation {
                name: staging.name.clone(),
                bytes,
                message: "readback memory is not host-visible".into(),
            }),
        }
    }

    /// Writes `data` into an existing device buffer (e.g. to poison an output before a test).
    pub fn write_buffer(&self, buffer: &Buffer, data: &[u8]) -> Result<()> {
        let staging = self.staging_with(&buffer.name, data)?;
        let len = (data.len() as u64).min(buffer.size);
        self.submit(&format!("write {}", buffer.name), |cmd| {
            cmd.copy_buffer(&staging, buffer, len);
        })
    }

    /// Creates an image (2-D when `extent[2] == 1` and `dim3` is false, else 3-D).
    pub fn create_image(
        &self,
        name: &str,
        extent: [u32; 3],
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        dim3: bool,
    ) -> Result<Image> {
        self.create_image_layers(name, extent, 1, format, usage, dim3)
    }

    /// Like [`Gpu::create_image`], with `layers` array layers (2-D images only), viewed as an
    /// array when there are several.
    pub fn create_image_layers(
        &self,
        name: &str,
        extent: [u32; 3],
        layers: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        dim3: bool,
    ) -> Result<Image> {
        self.create_image_inner(name, extent, layers, format, usage, dim3, 1)
    }

    /// A 2-D attachment with `samples` samples per pixel (a multisampled colour or depth
    /// target; see [`Gpu::attachment_sample_counts`]).
    pub fn create_image_multisampled(
        &self,
        name: &str,
        size: [u32; 2],
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        samples: u32,
    ) -> Result<Image> {
        let extent = [size[0], size[1], 1];
        self.create_image_inner(name, extent, 1, format, usage, false, samples)
    }

    #[allow(clippy::too_many_arguments)]
    fn create_image_inner(
        &self,
        name: &str,
        extent: [u32; 3],
        layers: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        dim3: bool,
        samples: u32,
    ) -> Result<Image> {
        let samples = crate::pipeline::sample_count_flag(samples)
            .filter(|&f| samples == 1 || self.attachment_sample_counts().contains(f))
            .ok_or_else(|| GpuError::Unsupported {
                device: self.caps().device_name.clone(),
                what: format!("{samples} samples per pixel for '{name}'"),
            })?;
        let layers = if dim3 { 1 } else { layers.max(1) };
        let max = self.caps().max_image_dimension_3d;
        if dim3 && extent.iter().any(|&d| d > max) {
            return Err(GpuError::ImageTooLarge {
                name: name.into(),
                extent: extent.iter().copied().max().unwrap_or(0),
                limit: max,
            });
        }
        let extent3 = vk::Extent3D {
            width: extent[0],
            height: extent[1],
            depth: extent[2],
        };
        let (image_type, view_type) = if dim3 {
            (vk::ImageType::TYPE_3D, vk::ImageViewType::TYPE_3D)
        } else if layers > 1 {
            (vk::ImageType::TYPE_2D, vk::ImageViewType::TYPE_2D_ARRAY)
        } else {
            (vk::ImageType::TYPE_2D, vk::ImageViewType::TYPE_2D)
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(image_type)
            .format(format)
            .extent(extent3)
            .mip_levels(1)
            .array_layers(layers)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: the create info is valid: the sample count and 3-D extent were checked
        // against the device above.
        let handle = unsafe { self.device.create_image(&info, None) }.call("vkCreateImage")?;
        // From here on dropping `image` destroys what has been made so far (the view is null
        // until created).
        let mut image = Image {
            handle,
            view: vk::ImageView::null(),
            format,
            extent: extent3,
            layers,
            name: name.into(),
            allocation: None,
            shared: self.shared.clone(),
        };
        // SAFETY: `handle` is a live image of this device.
        let requirements = unsafe { self.device.get_image_memory_requirements(handle) };
        self.check_fits(name, requirements.size)?;
        let allocation = match self.shared.allocator.lock() {
            Ok(mut a) => a
                .allocate(&AllocationCreateDesc {
                    name,
                    requirements,
                    location: MemoryLocation::GpuOnly,
                    linear: false,
                    allocation_scheme: AllocationScheme::GpuAllocatorManaged,
                })
                .map_err(|e| allocation_error(name, requirements.size, e)),
            Err(_) => Err(GpuError::Allocation {
                name: name.into(),
                bytes: requirements.size,
                message: "allocator lock poisoned".into(),
            }),
        };
        let allocation = allocation?;
        // SAFETY: this allocation backs only this image, and `Drop` destroys the image before
        // it frees the allocation, as `memory` requires.
        let (memory, offset) = (unsafe { allocation.memory() }, allocation.offset());
        image.allocation = Some(allocation);
        // SAFETY: the allocation was made for this image's requirements, at a suitably aligned
        // offset, and the image has no memory bound yet.
        unsafe { self.device.bind_image_memory(handle, memory, offset) }
            .call("vkBindImageMemory")?;
        self.set_name(handle, name);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(handle)
            .view_type(view_type)
            .format(format)
            .subresource_range(full_range(format, layers));
        // SAFETY: the image is live with memory bound, and the view's type, format and range
        // match how it was created.
        image.view =
            unsafe { self.device.create_image_view(&view_info, None) }.call("vkCreateImageView")?;
        Ok(image)
    }

    /// A sampled 3-D image filled from tightly packed texels, left in shader-read layout.
    pub fn upload_image_3d(
        &self,
        name: &str,
        extent: [u32; 3],
        format: vk::Format,
        texels: &[u8],
    ) -> Result<Image> {
        let image = self.create_image(
            name,
            extent,
            format,
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            true,
        )?;
        let staging = self.staging_with(name, texels)?;
        self.submit(&format!("upload {name}"), |cmd| {
            cmd.copy_buffer_to_image(&staging, &image);
        })?;
        Ok(image)
    }

    /// Bytes currently allocated through the device's allocator (by every live buffer and
    /// image), from its bookkeeping; for checking that objects free their memory.
    pub fn allocated_bytes(&self) -> u64 {
        self.memory_report().allocated_bytes
    }

    /// The allocator's bookkeeping: what live buffers and images hold, and the device memory
    /// blocks it keeps to place them in (kept after their objects go, for reuse).
    pub fn memory_report(&self) -> MemoryReport {
        match self.shared.allocator.lock() {
            Ok(a) => {
                let report = a.generate_report();
                MemoryReport {
                    allocated_bytes: report.total_allocated_bytes,
                    allocations: report.allocations.len() as u64,
                    reserved_bytes: report.total_capacity_bytes,
                    blocks: report.blocks.len() as u64,
                }
            }
            Err(_) => MemoryReport::default(),
        }
    }
}

/// Device memory in use, from the allocator ([`Gpu::memory_report`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryReport {
    /// Bytes held by live buffers and images.
    pub allocated_bytes: u64,
    /// Live allocations (one per buffer or image).
    pub allocations: u64,
    /// Bytes of the device memory blocks the allocator holds.
    pub reserved_bytes: u64,
    pub blocks: u64,
}

/// Depth formats are viewed and transitioned through their depth aspect, all others as colour.
pub(crate) fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D16_UNORM | vk::Format::D32_SFLOAT | vk::Format::X8_D24_UNORM_PACK32 => {
            vk::ImageAspectFlags::DEPTH
        }
        vk::Format::D24_UNORM_S8_UINT | vk::Format::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::COLOR,
    }
}

pub(crate) fn full_range(format: vk::Format, layers: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect_of(format),
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: layers,
    }
}

/// Small GPU values (counters, statistics) that a frame copies to the host at its end, or a
/// shader writes straight into ([`Readback::storage`]), and the host reads once the frame's
/// submission finished: one host-visible buffer made once, so a read needs no staging buffer
/// and no submission of its own (as [`Gpu::read_buffer`] does).
pub struct Readback {
    buffer: Buffer,
}

impl Gpu {
    /// A readback of `bytes`, zero until a copy lands.
    pub fn create_readback(&self, name: &str, bytes: u64) -> Result<Readback> {
        let mut buffer = self.create_buffer(
            name,
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        if let Some(bytes) = buffer.mapped_mut() {
            bytes.fill(0);
        }
        Ok(Readback { buffer })
    }
}

impl Readback {
    /// The readback as a storage buffer for a shader to write into: a small copy costs a
    /// frame more than the shader's few stores do.
    pub fn storage(&self) -> &Buffer {
        &self.buffer
    }

    /// Records a copy of the first `bytes` of `src` to `offset` in the readback, then a
    /// barrier (so later commands may write `src` again); record a barrier before it so that
    /// it follows the writes to `src`. Panics when the range passes either buffer: a caller's
    /// layout error.
    pub fn record_copy(&self, rec: &crate::Recorder, src: &Buffer, offset: u64, bytes: u64) {
        self.record_copies(rec, &[(src, offset, bytes)]);
    }

    /// Records the copies of the first `bytes` of each `src` to its `offset`, then one barrier:
    /// as [`Self::record_copy`] for each, without a barrier between them.
    pub fn record_copies(&self, rec: &crate::Recorder, copies: &[(&Buffer, u64, u64)]) {
        for &(src, offset, bytes) in copies {
            assert!(
                bytes <= src.size && offset + bytes <= self.buffer.size,
                "readback of {bytes} bytes of '{}' at {offset} into '{}' ({} bytes)",
                src.name,
                self.buffer.name,
                self.buffer.size
            );
            rec.copy_buffer_range(src, 0, &self.buffer, offset, bytes);
        }
        rec.barrier();
    }

    /// The bytes as the last finished submission left them (zeros before any).
    pub fn bytes(&self) -> &[u8] {
        self.buffer.mapped().unwrap_or(&[])
    }
}
