//! Buffers and images with their allocations, plus staging upload and readback.

use crate::context::Gpu;
use crate::error::{GpuError, Result, VkContext};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;

pub struct Buffer {
    pub handle: vk::Buffer,
    pub size: u64,
    pub name: String,
    allocation: Option<Allocation>,
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

pub struct Image {
    pub handle: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent3D,
    /// Array layers of a 2-D image (one per view when rendering with multiview).
    pub layers: u32,
    pub name: String,
    allocation: Option<Allocation>,
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
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let handle = unsafe { self.device.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        let requirements = unsafe { self.device.get_buffer_memory_requirements(handle) };
        let allocation = self
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
            });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                unsafe { self.device.destroy_buffer(handle, None) };
                return Err(allocation_error(name, size, e));
            }
        };
        unsafe {
            self.device
                .bind_buffer_memory(handle, allocation.memory(), allocation.offset())
        }
        .call("vkBindBufferMemory")?;
        self.set_name(handle, name);
        Ok(Buffer {
            handle,
            size,
            name: name.to_string(),
            allocation: Some(allocation),
        })
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
        let result = self.submit(&format!("upload {name}"), |cmd| {
            cmd.copy_buffer(&staging, &buffer, data.len() as u64);
        });
        self.destroy_buffer(staging);
        result.map(|_| buffer)
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
                self.destroy_buffer(staging);
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
        let staging = self.create_buffer(
            &format!("{} (readback)", buffer.name),
            buffer.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let result = self.submit(&format!("read back {}", buffer.name), |cmd| {
            cmd.copy_buffer(buffer, &staging, buffer.size);
        });
        let bytes = result.map(|_| {
            staging
                .mapped()
                .map(|m| m[..buffer.size as usize].to_vec())
                .unwrap_or_default()
        });
        self.destroy_buffer(staging);
        bytes
    }

    /// Writes `data` into an existing device buffer (e.g. to poison an output before a test).
    pub fn write_buffer(&self, buffer: &Buffer, data: &[u8]) -> Result<()> {
        let staging = self.staging_with(&buffer.name, data)?;
        let len = (data.len() as u64).min(buffer.size);
        let result = self.submit(&format!("write {}", buffer.name), |cmd| {
            cmd.copy_buffer(&staging, buffer, len);
        });
        self.destroy_buffer(staging);
        result
    }

    pub fn destroy_buffer(&self, mut buffer: Buffer) {
        if let Some(a) = buffer.allocation.take() {
            if let Ok(mut alloc) = self.allocator.lock() {
                let _ = alloc.free(a);
            }
        }
        unsafe { self.device.destroy_buffer(buffer.handle, None) };
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
            return Err(GpuError::TooLarge {
                name: name.into(),
                bytes: extent.iter().copied().max().unwrap_or(0) as u64,
                limit: max as u64,
                what: "3-D image size (texels per axis)",
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
        let handle = unsafe { self.device.create_image(&info, None) }.call("vkCreateImage")?;
        let requirements = unsafe { self.device.get_image_memory_requirements(handle) };
        if let Err(e) = self.check_fits(name, requirements.size) {
            unsafe { self.device.destroy_image(handle, None) };
            return Err(e);
        }
        let allocation = match self.allocator.lock() {
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
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                unsafe { self.device.destroy_image(handle, None) };
                return Err(e);
            }
        };
        unsafe {
            self.device
                .bind_image_memory(handle, allocation.memory(), allocation.offset())
        }
        .call("vkBindImageMemory")?;
        self.set_name(handle, name);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(handle)
            .view_type(view_type)
            .format(format)
            .subresource_range(full_range(format, layers));
        let view =
            unsafe { self.device.create_image_view(&view_info, None) }.call("vkCreateImageView")?;
        Ok(Image {
            handle,
            view,
            format,
            extent: extent3,
            layers,
            name: name.into(),
            allocation: Some(allocation),
        })
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
        let staging = match self.staging_with(name, texels) {
            Ok(s) => s,
            Err(e) => {
                self.destroy_image(image);
                return Err(e);
            }
        };
        let result = self.submit(&format!("upload {name}"), |cmd| {
            cmd.copy_buffer_to_image(&staging, &image);
        });
        self.destroy_buffer(staging);
        match result {
            Ok(()) => Ok(image),
            Err(e) => {
                self.destroy_image(image);
                Err(e)
            }
        }
    }

    pub fn destroy_image(&self, mut image: Image) {
        unsafe { self.device.destroy_image_view(image.view, None) };
        if let Some(a) = image.allocation.take() {
            if let Ok(mut alloc) = self.allocator.lock() {
                let _ = alloc.free(a);
            }
        }
        unsafe { self.device.destroy_image(image.handle, None) };
    }
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
