//! The attachments `param-tess` draws into (the image they end in is the caller's `Target`).

use super::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::error::Result;
use tessera_data::View;
use tessera_gpu::{vk, Gpu, Image};

/// The attachments of one view's raster.
pub struct TessFrame {
    /// Single-sample colour: drawn into, or the MSAA resolve's target; read by the downsample.
    pub colour: Image,
    pub msaa_colour: Option<Image>,
    pub depth: Image,
    pub(super) raster: (u32, u32),
    pub(super) samples: u32,
}

impl TessFrame {
    /// Attachments for `view`'s raster with `msaa` samples per pixel.
    pub fn new(gpu: &Gpu, view: &View, msaa: u32) -> Result<TessFrame> {
        let (w, h) = view.raster_size();
        let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        let colour = gpu.create_image(
            "param tess colour",
            [w, h, 1],
            COLOR_FORMAT,
            attachment | vk::ImageUsageFlags::STORAGE,
            false,
        )?;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let depth = gpu.create_image_multisampled(
            "param tess depth",
            [w, h],
            DEPTH_FORMAT,
            depth_usage,
            msaa,
        )?;
        let msaa_colour = if msaa > 1 {
            let name = "param tess colour (multisampled)";
            Some(gpu.create_image_multisampled(name, [w, h], COLOR_FORMAT, attachment, msaa)?)
        } else {
            None
        };
        Ok(TessFrame {
            colour,
            msaa_colour,
            depth,
            raster: (w, h),
            samples: msaa,
        })
    }
}
