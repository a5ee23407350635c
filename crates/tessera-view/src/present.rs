//! Showing a frame: the rendered image copied from the GPU target into the swapchain image
//! (no read back), the controls drawn over it with egui's Vulkan renderer, then presented.

use crate::error::ViewError;
use egui_ash_renderer::{DynamicRendering, Options, Renderer as OverlayRenderer};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};
use tessera::target::Target;
use tessera_gpu::{vk, Gpu, Image, Swapchain};

/// The window's swapchain, the image the target's pixels pass through on their way to it,
/// and egui's renderer.
pub struct Presenter {
    // Declared first so it is dropped first: it destroys its objects on the device, which
    // `swapchain` keeps alive.
    overlay: OverlayRenderer,
    /// An `R8G8B8A8_UNORM` image of the target's size (made again when the size changes).
    staging: Option<Image>,
    swapchain: Swapchain,
    /// Set when the swapchain no longer fits the window.
    stale: bool,
}

fn overlay_error(e: egui_ash_renderer::RendererError) -> ViewError {
    ViewError::Overlay(e.to_string())
}

impl Presenter {
    pub fn new(
        gpu: &Gpu,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        size: (u32, u32),
    ) -> Result<Presenter, ViewError> {
        let swapchain = Swapchain::new(gpu, display, window, size)?;
        let overlay = OverlayRenderer::with_default_allocator(
            gpu.instance(),
            gpu.physical_device(),
            gpu.device().clone(),
            DynamicRendering {
                color_attachment_format: swapchain.format(),
                depth_attachment_format: None,
            },
            Options {
                in_flight_frames: 1,
                // The swapchain is UNORM (see `Swapchain`): egui's shader encodes sRGB itself.
                srgb_framebuffer: false,
                ..Options::default()
            },
        )
        .map_err(overlay_error)?;
        Ok(Presenter {
            overlay,
            staging: None,
            swapchain,
            stale: false,
        })
    }

    /// The size images must have to be shown.
    pub fn size(&self) -> (u32, u32) {
        let e = self.swapchain.extent();
        (e.width, e.height)
    }

    /// Asks for the swapchain to be made again before the next frame (the window changed).
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Makes the swapchain fit a window of `size` pixels when it no longer does.
    pub fn fit(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<(), ViewError> {
        if self.stale || self.size() != size {
            self.swapchain.resize(gpu, size)?;
            self.stale = false;
        }
        Ok(())
    }

    /// Shows `target` (of [`Presenter::size`]) with `overlay` drawn over it; returns `false`
    /// when the swapchain turned out not to fit and nothing was shown.
    pub fn show(
        &mut self,
        gpu: &Gpu,
        target: &Target,
        textures: &egui::TexturesDelta,
        pixels_per_point: f32,
        primitives: &[egui::ClippedPrimitive],
    ) -> Result<bool, ViewError> {
        let (queue, pool) = gpu.queue_and_pool();
        self.overlay
            .set_textures(queue, pool, textures.set.as_slice())
            .map_err(overlay_error)?;
        let size = (target.width, target.height);
        if self
            .staging
            .as_ref()
            .map(|s| (s.extent.width, s.extent.height))
            != Some(size)
        {
            self.staging = None;
            self.staging = Some(gpu.create_image(
                "presented pixels",
                [size.0, size.1, 1],
                vk::Format::R8G8B8A8_UNORM,
                // Sampled only because every image gets a view, which needs a viewable usage.
                vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::SAMPLED,
                false,
            )?);
        }
        let Some(staging) = &self.staging else {
            return Ok(false); // made just above
        };
        let Some(image) = self.swapchain.acquire()? else {
            self.stale = true;
            self.overlay
                .free_textures(&textures.free)
                .map_err(overlay_error)?;
            return Ok(false);
        };
        // When the window changed since the frame was rendered, the acquired image must still
        // be presented: it is shown cleared this once, and the next frame fits.
        let fits = (image.extent.width, image.extent.height) == size;
        self.stale |= !fits;
        let mut drawn = Ok(());
        let overlay_renderer = &mut self.overlay;
        gpu.submit("present", |rec| {
            if fits {
                rec.copy_pixels_to_swap_image(&target.pixels, staging, &image);
            } else {
                rec.clear_swap_image(&image);
            }
            rec.begin_overlay(&image);
            if fits {
                drawn =
                    overlay_renderer.cmd_draw(rec.cmd, image.extent, pixels_per_point, primitives);
            }
            rec.end_overlay(&image);
        })?;
        drawn.map_err(overlay_error)?;
        if !self.swapchain.present(gpu, &image)? {
            self.stale = true;
        }
        self.overlay
            .free_textures(&textures.free)
            .map_err(overlay_error)?;
        Ok(fits)
    }
}
