//! Rendering stored isosurfaces (meshlets, PMB) through the front door in tests: one camera,
//! image size and look for all, and the paths a device can draw them on.

use tessera::path::{PathChoice, Support};
use tessera::renderer::{self, Culling, Renderer, RendererOptions, Technique};
use tessera_data::scene::{Appearance, Dataset, LoadOptions};
use tessera_data::{IsoValue, OrbitCamera, RgbaImage};
use tessera_gpu::Gpu;

pub const SIZE: (u32, u32) = (96, 72);

pub fn load(spec: &str) -> Dataset {
    Dataset::load(spec, &LoadOptions::default()).unwrap_or_else(|e| panic!("{spec}: {e}"))
}

pub fn camera(distance: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg: 35.0,
        elevation_deg: 25.0,
        distance,
        ..OrbitCamera::default()
    }
}

pub fn look(iso: f32) -> Appearance {
    Appearance {
        iso: IsoValue::Normalized(iso),
        ..Appearance::default()
    }
}

/// The paths `support` says this device has, the others reported as skipped.
pub fn supported_paths(support: &Support) -> Vec<PathChoice> {
    let mut out = Vec::new();
    if support.compute {
        out.push(PathChoice::Compute);
    } else {
        super::skip("compute path", &format!("no {}", support.compute_needs));
    }
    if support.graphics {
        out.push(PathChoice::Graphics);
    } else {
        super::skip("graphics path", &format!("no {}", support.graphics_needs));
    }
    out
}

/// The paths this device can draw meshlets on (direct's), the others reported as skipped.
pub fn meshlet_paths(gpu: &Gpu) -> Vec<PathChoice> {
    let caps = gpu.caps();
    supported_paths(&Support {
        graphics: caps.mesh_shader && caps.task_shader,
        graphics_needs: "task/mesh shaders",
        compute: caps.buffer_int64_atomics,
        compute_needs: "64-bit buffer atomics",
    })
}

/// A renderer of `technique` with `options`, holding `data` at normalized isovalue `iso`.
pub fn renderer_with(
    gpu: &Gpu,
    technique: Technique,
    options: &RendererOptions,
    data: &Dataset,
    iso: f32,
) -> Box<dyn Renderer> {
    let mut r = renderer::create(gpu, technique, options).unwrap();
    r.set_appearance(gpu, &look(iso)).unwrap();
    r.set_data(gpu, data).unwrap();
    r
}

pub fn renderer_for(
    gpu: &Gpu,
    technique: Technique,
    path: PathChoice,
    culling: bool,
    data: &Dataset,
    iso: f32,
) -> Box<dyn Renderer> {
    let options = RendererOptions {
        path,
        culling: if culling { Culling::On } else { Culling::Off },
        ..RendererOptions::default()
    };
    renderer_with(gpu, technique, &options, data, iso)
}

/// One image of `camera(distance)` with the frame's stats, rendered into a poisoned target
/// so that a pixel nothing wrote fails.
pub fn render_counting(
    gpu: &Gpu,
    r: &mut dyn Renderer,
    distance: f32,
) -> (RgbaImage, renderer::FrameStats) {
    let view = r.view(&camera(distance), SIZE).unwrap();
    let mut frame = renderer::Frame::new(gpu, SIZE).unwrap();
    frame.target.poison(gpu, u32::MAX).unwrap();
    frame.render(gpu, r, &view).unwrap();
    let image = frame.target.read(gpu).unwrap();
    assert!(!image.pixels.contains(&u32::MAX), "unwritten pixels");
    (image, r.stats())
}

/// A frame counter by name, 0 where the technique does not count it.
pub fn detail(stats: &renderer::FrameStats, name: &str) -> u64 {
    stats.details.get(name).copied().unwrap_or(0)
}
