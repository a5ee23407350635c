//! Set-up shared by the front door's tests: a data set from a spec, one camera and image
//! size, a renderer holding data, and the image of one frame.

use tessera::renderer::{self, Frame, Renderer, RendererOptions, Technique};
use tessera_data::scene::{Dataset, LoadOptions};
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

pub const SIZE: (u32, u32) = (96, 64);

pub fn load(spec: &str) -> Dataset {
    Dataset::load(spec, &LoadOptions::default()).unwrap_or_else(|e| panic!("{spec}: {e}"))
}

pub fn camera() -> OrbitCamera {
    OrbitCamera {
        azimuth_deg: 35.0,
        elevation_deg: 25.0,
        distance: 1.9,
        ..OrbitCamera::default()
    }
}

pub fn with_data(
    gpu: &Gpu,
    technique: Technique,
    options: RendererOptions,
    data: &Dataset,
) -> Box<dyn Renderer> {
    let mut r = renderer::create(gpu, technique, &options).unwrap();
    r.set_data(gpu, data).unwrap();
    r
}

/// The image of one mono frame of `view`.
pub fn frame_pixels_of(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    view: &tessera_data::View,
) -> Vec<u32> {
    let mut frame = Frame::new(gpu, view.size).unwrap();
    frame.render(gpu, renderer, view).unwrap();
    frame.target.read(gpu).unwrap().pixels
}
