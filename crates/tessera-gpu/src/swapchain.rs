//! Presenting to a window: its surface and swapchain, made again when the window's size
//! changes. It knows nothing of what is drawn: a caller acquires an image, records into it
//! within a [`Gpu::submit`] (which waits for the work) and presents it.
//!
//! Since every submission is waited for on the host, presenting needs no semaphores: the
//! acquire is waited for through a fence, and the image's writes are complete when
//! [`Swapchain::present`] is called.

use crate::commands::Recorder;
use crate::context::{Gpu, GpuOptions};
use crate::error::{GpuError, Result, VkContext};
use crate::memory::{Buffer, Image};
use crate::shared::DeviceShared;
use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};
use std::ffi::CStr;
use std::sync::Arc;

impl Gpu {
    /// Opens the device with the instance extensions that surfaces of `display` need.
    pub fn for_display(options: &GpuOptions, display: RawDisplayHandle) -> Result<Gpu> {
        let names = ash_window::enumerate_required_extensions(display)
            .call("enumerating the window system's Vulkan extensions")?;
        let names: Vec<&CStr> = names
            .iter()
            // SAFETY: ash-window returns pointers to its static NUL-terminated extension names.
            .map(|&p| unsafe { CStr::from_ptr(p) })
            .collect();
        Gpu::with_instance_extensions(options, &names)
    }

    /// The queue and command pool, for a library that submits its own uploads (an overlay's
    /// font textures). Use them only on the thread that owns this `Gpu`, between
    /// [`Gpu::submit`] calls, and wait for the work before the next one.
    pub fn queue_and_pool(&self) -> (vk::Queue, vk::CommandPool) {
        (self.queue, self.command_pool)
    }

    pub fn instance(&self) -> &ash::Instance {
        &self.shared.instance
    }
}

/// A window's surface and swapchain; destroyed when dropped (after the device went idle).
pub struct Swapchain {
    surface_loader: ash::khr::surface::Instance,
    surface: vk::SurfaceKHR,
    loader: ash::khr::swapchain::Device,
    handle: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    views: Vec<vk::ImageView>,
    format: vk::Format,
    extent: vk::Extent2D,
    /// Signalled when an acquired image may be written; waited for on the host.
    acquired: vk::Fence,
    shared: Arc<DeviceShared>,
}

/// An image acquired from the swapchain, to be written and presented.
#[derive(Debug, Clone, Copy)]
pub struct SwapImage {
    pub index: u32,
    pub image: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
}

/// Formats whose bytes are shown as they are, with no sRGB encoding on write: images that
/// the renderer wrote as display values (RGBA8) stay the same on screen and in screenshots.
const PREFERRED_FORMATS: [vk::Format; 2] = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM];

impl Swapchain {
    /// A surface for the window and a swapchain of `size` pixels (or the surface's own size
    /// where the window system fixes it).
    pub fn new(
        gpu: &Gpu,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        size: (u32, u32),
    ) -> Result<Swapchain> {
        let shared = gpu.shared.clone();
        // SAFETY: the handles come from a live window the caller keeps open while the
        // swapchain exists (it is dropped before the window); the instance has the window
        // system's extensions (`Gpu::for_display`).
        let surface = unsafe {
            ash_window::create_surface(&shared._entry, &shared.instance, display, window, None)
        }
        .call("vkCreateSurfaceKHR")?;
        let surface_loader = ash::khr::surface::Instance::new(&shared._entry, &shared.instance);
        let loader = ash::khr::swapchain::Device::new(&shared.instance, &gpu.device);
        // SAFETY: a plain create info for a fence of this device.
        let acquired = unsafe {
            gpu.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        };
        let mut swapchain = Swapchain {
            surface_loader,
            surface,
            loader,
            handle: vk::SwapchainKHR::null(),
            images: Vec::new(),
            views: Vec::new(),
            format: vk::Format::UNDEFINED,
            extent: vk::Extent2D::default(),
            acquired: vk::Fence::null(),
            shared,
        };
        // From here a failure drops `swapchain`, which destroys what was made so far.
        swapchain.acquired = acquired.call("vkCreateFence")?;
        // SAFETY: the surface was made on this instance, the queue family is the device's.
        let supported = unsafe {
            swapchain
                .surface_loader
                .get_physical_device_surface_support(
                    gpu.physical_device(),
                    gpu.queue_family,
                    surface,
                )
        }
        .call("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(GpuError::Unsupported {
                device: gpu.caps().device_name.clone(),
                what: "presenting to this window from its queue".into(),
            });
        }
        swapchain.resize(gpu, size)?;
        Ok(swapchain)
    }

    pub fn format(&self) -> vk::Format {
        self.format
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// Makes the swapchain again for a window of `size` pixels; the old images must no longer
    /// be in use (every submission is waited for, so they are not).
    pub fn resize(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<()> {
        let physical = gpu.physical_device();
        // SAFETY: plain queries of a live surface on the device's physical device.
        let (caps, formats) = unsafe {
            (
                self.surface_loader
                    .get_physical_device_surface_capabilities(physical, self.surface)
                    .call("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                self.surface_loader
                    .get_physical_device_surface_formats(physical, self.surface)
                    .call("vkGetPhysicalDeviceSurfaceFormatsKHR")?,
            )
        };
        let format = PREFERRED_FORMATS
            .iter()
            .find_map(|&f| formats.iter().find(|s| s.format == f))
            .or(formats.first())
            .copied()
            .ok_or_else(|| GpuError::Unsupported {
                device: gpu.caps().device_name.clone(),
                what: "a surface format".into(),
            })?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .0
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size
                    .1
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let old = self.handle;
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(self.surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::COLOR_ATTACHMENT)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            // FIFO is the one mode every device has; frames wait for the display, not the GPU.
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old);
        self.destroy_views();
        // SAFETY: the create info names this live surface; `old` (retired by this call) is
        // no longer used once the device is idle, which every waited submission leaves it.
        let made = unsafe { self.loader.create_swapchain(&info, None) };
        // SAFETY: the old swapchain's images are not in use (see above); it goes whatever the
        // outcome, as a failed creation leaves it retired too.
        unsafe { self.loader.destroy_swapchain(old, None) };
        self.handle = vk::SwapchainKHR::null();
        self.handle = made.call("vkCreateSwapchainKHR")?;
        self.format = format.format;
        self.extent = extent;
        // SAFETY: a plain query of the swapchain just made.
        self.images = unsafe { self.loader.get_swapchain_images(self.handle) }
            .call("vkGetSwapchainImagesKHR")?;
        for &image in &self.images {
            let info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(self.format)
                .subresource_range(colour_range());
            // SAFETY: `image` belongs to the live swapchain and the view matches its format.
            let view =
                unsafe { gpu.device.create_image_view(&info, None) }.call("vkCreateImageView")?;
            self.views.push(view);
        }
        Ok(())
    }

    /// The next image to write, once it may be written; `None` when the swapchain no longer
    /// fits the window and must be made again ([`Swapchain::resize`]).
    pub fn acquire(&mut self) -> Result<Option<SwapImage>> {
        let device = &self.shared.device;
        // SAFETY: the swapchain and fence are live and the fence unsignalled (reset after
        // every wait below).
        let acquired = unsafe {
            self.loader.acquire_next_image(
                self.handle,
                u64::MAX,
                vk::Semaphore::null(),
                self.acquired,
            )
        };
        let index = match acquired {
            Ok((index, _suboptimal)) => index,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => return Ok(None),
            Err(result) => return Err(GpuError::of_call("vkAcquireNextImageKHR", result)),
        };
        // SAFETY: the fence was handed to the acquire above, which signals it.
        unsafe {
            device
                .wait_for_fences(&[self.acquired], true, self.shared.timeout_ns)
                .call("vkWaitForFences")?;
            device
                .reset_fences(&[self.acquired])
                .call("vkResetFences")?;
        }
        Ok(Some(SwapImage {
            index,
            image: self.images[index as usize],
            view: self.views[index as usize],
            format: self.format,
            extent: self.extent,
        }))
    }

    /// Shows an image acquired and written (its submission waited for); `false` when the
    /// swapchain no longer fits the window and must be made again.
    pub fn present(&self, gpu: &Gpu, image: &SwapImage) -> Result<bool> {
        let swapchains = [self.handle];
        let indices = [image.index];
        let info = vk::PresentInfoKHR::default()
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired from this swapchain and its writes are complete (the
        // submission that made them was waited for); the queue is used only on this thread.
        match unsafe { self.loader.queue_present(gpu.queue, &info) } {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(result) => Err(GpuError::of_call("vkQueuePresentKHR", result)),
        }
    }

    fn destroy_views(&mut self) {
        for view in self.views.drain(..) {
            // SAFETY: views of swapchain images are used only by waited submissions.
            unsafe { self.shared.device.destroy_image_view(view, None) };
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        if self.shared.hung.load(std::sync::atomic::Ordering::Acquire) {
            return; // see `DeviceShared::hung`
        }
        // SAFETY: after the wait nothing uses the views, images or fence; the swapchain goes
        // before its surface, and the device and instance outlive both (held in `shared`).
        unsafe {
            let _ = self.shared.device.device_wait_idle();
            self.destroy_views();
            self.loader.destroy_swapchain(self.handle, None);
            self.surface_loader.destroy_surface(self.surface, None);
            self.shared.device.destroy_fence(self.acquired, None);
        }
    }
}

fn colour_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

impl Recorder<'_> {
    /// Copies packed RGBA8 `pixels` (rows top to bottom, `staging`'s size) into `to`: through
    /// `staging`, an `R8G8B8A8_UNORM` image with transfer usage, and a blit, which swizzles
    /// the channels into the swapchain's format. Leaves `to` ready to draw on
    /// (`COLOR_ATTACHMENT_OPTIMAL`). The image must be as large as `staging`.
    pub fn copy_pixels_to_swap_image(&self, pixels: &Buffer, staging: &Image, to: &SwapImage) {
        let device = &self.gpu.device;
        // Earlier submissions wrote `pixels`; make those writes visible to the copy.
        self.barrier();
        self.layout(
            staging.handle,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let region = [vk::BufferImageCopy::default()
            .image_subresource(layers)
            .image_extent(staging.extent)];
        let corner = vk::Offset3D {
            x: staging.extent.width as i32,
            y: staging.extent.height as i32,
            z: 1,
        };
        let blit = [vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner])];
        // SAFETY: `self.cmd` is recording; `pixels` and `staging` are live objects of this
        // device and `to` an acquired swapchain image; each is moved into the layout its
        // command names just before it, and the blit stays within both images.
        unsafe {
            device.cmd_copy_buffer_to_image(
                self.cmd,
                pixels.handle,
                staging.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &region,
            );
            self.layout(
                staging.handle,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            );
            self.layout(
                to.image,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            );
            device.cmd_blit_image(
                self.cmd,
                staging.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                to.image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &blit,
                vk::Filter::NEAREST,
            );
        }
        self.layout(
            to.image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
    }

    /// Clears `to` to black and leaves it ready to draw on, for a frame that has no image of
    /// its size (the window changed size since it was rendered).
    pub fn clear_swap_image(&self, to: &SwapImage) {
        self.layout(
            to.image,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
        let black = vk::ClearColorValue {
            float32: [0.0, 0.0, 0.0, 1.0],
        };
        // SAFETY: `self.cmd` is recording; `to` is an acquired image in the layout named.
        unsafe {
            self.gpu.device.cmd_clear_color_image(
                self.cmd,
                to.image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &black,
                &[colour_range()],
            )
        };
        self.layout(
            to.image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
    }

    /// Begins dynamic rendering onto `to` (after [`Recorder::copy_pixels_to_swap_image`]),
    /// keeping what is there: for an overlay drawn over the image.
    pub fn begin_overlay(&self, to: &SwapImage) {
        let attachments = [vk::RenderingAttachmentInfo::default()
            .image_view(to.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let info = vk::RenderingInfo::default()
            .render_area(to.extent.into())
            .layer_count(1)
            .color_attachments(&attachments);
        // SAFETY: `self.cmd` is recording outside rendering; the view is the acquired image's,
        // in the layout named.
        unsafe { self.gpu.device.cmd_begin_rendering(self.cmd, &info) };
    }

    /// Ends the overlay's rendering and hands `to` over for presenting.
    pub fn end_overlay(&self, to: &SwapImage) {
        // SAFETY: `self.cmd` is recording inside the rendering `begin_overlay` began.
        unsafe { self.gpu.device.cmd_end_rendering(self.cmd) };
        self.layout(
            to.image,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::PRESENT_SRC_KHR,
        );
    }

    fn layout(&self, image: vk::Image, from: vk::ImageLayout, to: vk::ImageLayout) {
        self.layout_barrier(image, colour_range(), from, to);
    }
}
