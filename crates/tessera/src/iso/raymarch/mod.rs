//! Isosurface ray marching through a min-max octree — paper D's reference method.
//!
//! Per pixel: enter the volume's box, march at half-cell steps, skip to the exit of the largest
//! octree node whose value range excludes the isovalue, refine the first crossing with three
//! bisections, shade with central-difference normals and Gooch tones. Unlike the paper's
//! implementation the sample lattice is fixed per ray, so skipping never changes the result and
//! the image equals a plain march (the CPU reference, `tessera_data::raycast`).

use crate::builtin_shader;
use crate::config::volume_defines;
use crate::error::Result;
use crate::iso::minmax::MinMaxBuilder;
pub use crate::iso::PreparedVolume;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_data::{GridFrame, OrbitCamera, RgbaImage, ScalarType, View, Volume};
use tessera_gpu::{Binding, Gpu, Pipeline, Recorder, ShaderCompiler, Slot, Timer};

/// Push constants of `raymarch.comp.glsl` (its `RaymarchParams` block; a test holds the two to
/// the same layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct RaymarchParams {
    pub eye: [f32; 3],
    pub isovalue: f32,
    pub forward: [f32; 3],
    pub tan_half_fov_x: f32,
    pub right: [f32; 3],
    pub tan_half_fov_y: f32,
    pub up: [f32; 4],
    pub light: [f32; 4],
    pub grid_to_world: [f32; 4],
    pub dims: [u32; 3],
    pub octree_levels: u32,
    pub image: [u32; 4],
}

pub struct Raymarch {
    march: Pipeline,
    builder: MinMaxBuilder,
}

impl Raymarch {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<Raymarch> {
        let spirv = compiler.compile(
            &builtin_shader!("raymarch.comp.glsl"),
            &volume_defines(scalar),
        )?;
        let march = gpu.compute_pipeline(
            "raymarch",
            &spirv,
            &[
                Slot::Texture,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
                Slot::StorageBuffer,
            ],
        )?;
        Ok(Raymarch {
            march,
            builder: MinMaxBuilder::new(gpu, compiler, scalar)?,
        })
    }

    /// Uploads `volume` and builds its octree on the GPU.
    pub fn prepare(&self, gpu: &Gpu, volume: &Volume) -> Result<PreparedVolume> {
        PreparedVolume::new(gpu, &self.builder, volume)
    }

    /// Records the octree build alone (for timing it).
    /// The octree builder, for builds from other sources than the prepared volume's texture.
    pub fn builder(&self) -> &MinMaxBuilder {
        &self.builder
    }

    pub fn record_build(&self, rec: &Recorder, prepared: &PreparedVolume) {
        self.builder.record(rec, &prepared.volume, &prepared.octree);
    }

    pub fn params(
        prepared: &PreparedVolume,
        iso: f32,
        camera: &OrbitCamera,
        width: u32,
        height: u32,
    ) -> RaymarchParams {
        Self::params_for_view(prepared, iso, &View::of_unit_box(camera, (width, height)))
    }

    pub fn params_for_view(prepared: &PreparedVolume, iso: f32, view: &View) -> RaymarchParams {
        let dims = prepared.volume.dims;
        let frame = GridFrame::new(dims, prepared.spacing);
        let cam = view.grid_camera(&frame);
        let (width, height) = view.size;
        let v4 = |v: glam::Vec3, w: f32| [v.x, v.y, v.z, w];
        RaymarchParams {
            eye: cam.eye.to_array(),
            isovalue: iso,
            forward: cam.forward.to_array(),
            tan_half_fov_x: cam.tan_half_fov_x,
            right: cam.right.to_array(),
            tan_half_fov_y: cam.tan_half_fov_y,
            up: v4(cam.up, 0.0),
            light: v4(cam.light_world, 0.0),
            grid_to_world: v4(frame.grid_to_world, 0.0),
            dims,
            octree_levels: prepared.octree.level_dims.len() as u32,
            image: [width, height, 0, 0],
        }
    }

    /// Records one frame into `target`.
    pub fn record(
        &self,
        rec: &Recorder,
        prepared: &PreparedVolume,
        target: &Target,
        params: &RaymarchParams,
    ) {
        rec.dispatch(
            &self.march,
            &[
                Binding::Texture {
                    image: &prepared.volume.texture,
                    linear: false,
                },
                Binding::Buffer(&prepared.octree.nodes),
                Binding::Buffer(&prepared.octree.levels),
                Binding::Buffer(&target.pixels),
            ],
            bytemuck::bytes_of(params),
            [target.width, target.height, 1],
        );
    }

    /// Renders one frame and returns it with the GPU time of the march in milliseconds.
    pub fn render(
        &self,
        gpu: &Gpu,
        prepared: &PreparedVolume,
        target: &Target,
        iso: f32,
        camera: &OrbitCamera,
    ) -> Result<(RgbaImage, f64)> {
        let params = Self::params(prepared, iso, camera, target.width, target.height);
        let mut timer = Timer::new(gpu, 1)?;
        timer.reset(gpu);
        gpu.submit("raymarch", |rec| {
            timer.scope(rec, "raymarch", |rec| {
                self.record(rec, prepared, target, &params)
            });
        })?;
        let ms = timer.read_ms(gpu)?.first().map(|s| s.1).unwrap_or(0.0);
        Ok((target.read(gpu)?, ms))
    }
}
