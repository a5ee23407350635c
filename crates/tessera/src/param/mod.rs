//! `param-points`: parametric objects rendered point by point — paper E (Unterguggenberger et
//! al. 2024, "Fast Rendering of Parametric Objects on Modern GPUs"), its PATCH INITIALIZATION,
//! PATCH SUBDIVISION (§4.1) and POINT-BASED rendering (§4.3), all in compute.
//!
//! * [`scene`]: [`ParamScene`] (functions of `tessera_data::param` with transforms) and its
//!   upload; the GLSL functions mirror the CPU ones (sphere, heart, SH glyphs of any DIPY basis
//!   up to order [`scene::GPU_MAX_SH_ORDER`]).
//! * [`lod`]: patch initialization and up to `max_steps` indirect LOD steps, bit-exact to the
//!   CPU reference `tessera_data::param::run_lod` given the same sample positions.
//! * [`points`]: sampling each patch to render at about one sample per pixel of its extent,
//!   64-bit `atomicMin` into a depth|payload raster, resolve with shading and supersampling.
//!
//! Changes from the paper: the LOD stage shares samples through shared memory instead of
//! subgroup operations (no subgroup size assumed; one 64-invocation workgroup per patch); the
//! point pass samples patches in 8×8-cell tiles in shared memory instead of the paper's
//! 32-subgroup columns, and by default draws each cell of the sample grid at pixel centres
//! ([`Footprint::Cell`]) rather than splatting samples ([`Footprint::Pixel`], also offered),
//! which gives exact silhouettes without the paper's ε tuning; the payload stores
//! (object, u, v) rather than a colour, and a resolve shades.

pub mod lod;
pub mod points;
pub mod raytrace;
pub mod scene;
pub mod scenes;
pub mod tess;
pub mod user;

#[cfg(test)]
mod inlining_tests;

pub use lod::{GpuPatch, LodSample, LodSettings, LodStats};
pub use points::{Footprint, PointsFrame};
pub use scene::{GpuParamScene, ParamObject, ParamScene};
pub use tessera_data::View;

use crate::builtin_shader;
use crate::error::{Error, Result};
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use lod::{LodStage, SAMPLE_BYTES};
use points::PointPasses;
use tessera_data::{OrbitCamera, RgbaImage};
use tessera_gpu::{vk, Binding, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot};

/// Settings of `param-points`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamPointsOptions {
    /// `(t_u, t_v)` in raster pixels (paper: 84 for SH glyphs).
    pub thresholds: [f32; 2],
    /// LOD steps (paper: 12).
    pub max_steps: u32,
    pub frustum_culling: bool,
    /// Patches each patch list holds (32 bytes each, three lists).
    pub patch_capacity: u32,
    /// PATCH INITIALIZATION's optional uniform pre-split: each object starts as `k × k`
    /// patches (a power of two up to 16; 1 = the whole domain).
    pub pre_split: u32,
    pub footprint: Footprint,
    /// Samples per pixel of a patch's measured extent along each direction (1 = the paper's
    /// "about one sample per pixel"; [`Footprint::Pixel`] needs more to avoid holes).
    pub density: f32,
    /// Most grid cells per direction of one patch (bounds patches the step limit left large).
    pub max_side: u32,
    /// Render at `k × k` samples per pixel and average them in the resolve.
    pub supersample: u32,
}

impl Default for ParamPointsOptions {
    fn default() -> Self {
        ParamPointsOptions {
            thresholds: [tessera_data::param::lod::DEFAULT_THRESHOLD; 2],
            max_steps: tessera_data::param::lod::DEFAULT_MAX_STEPS,
            frustum_culling: true,
            patch_capacity: 1 << 20,
            pre_split: 1,
            footprint: Footprint::Cell,
            density: 1.0,
            max_side: 512,
            supersample: 1,
        }
    }
}

/// What one rendered frame did.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamFrameInfo {
    pub gpu_ms: f64,
    pub stats: LodStats,
}

/// Evaluation of one object at one `(u, v)` on the GPU ([`ParamPoints::probe`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ProbeResult {
    /// World position; `w` = the raw SH sum for glyphs (0 otherwise).
    pub position: [f32; 4],
    /// World normal (zero where degenerate).
    pub normal: [f32; 4],
    /// Base colour.
    pub colour: [f32; 4],
}

pub struct ParamPoints {
    pub(crate) lod: LodStage,
    passes: PointPasses,
    probe: Pipeline,
    options: ParamPointsOptions,
}

impl ParamPoints {
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        options: ParamPointsOptions,
    ) -> Result<ParamPoints> {
        if !gpu.caps().buffer_int64_atomics {
            return Err(Error::Invalid(format!(
                "param-points needs 64-bit buffer atomics, which {} lacks",
                gpu.caps().device_name
            )));
        }
        let usable = options.density > 0.0
            && options.density <= 16.0
            && (1..=1 << 14).contains(&options.max_side)
            && (1..=8).contains(&options.supersample);
        if !usable {
            return Err(Error::Invalid(format!(
                "param-points needs a density in (0, 16], max_side in 1..=16384 and \
                 supersampling in 1..=8, got {}, {} and {}",
                options.density, options.max_side, options.supersample
            )));
        }
        let lod = LodStage::new(
            gpu,
            compiler,
            LodSettings {
                thresholds: options.thresholds,
                max_steps: options.max_steps,
                frustum_culling: options.frustum_culling,
                capacity: options.patch_capacity,
                pre_split: options.pre_split,
            },
        )?;
        let passes = PointPasses::new(gpu, compiler)?;
        let probe = compiler
            .compile(
                &builtin_shader!("probe.comp.glsl"),
                &points::points_defines(),
            )
            .map_err(Error::from)
            .and_then(|s| {
                Ok(gpu.compute_pipeline("param probe", &s, &[Slot::StorageBuffer; 5])?)
            });
        let probe = probe?;
        Ok(ParamPoints {
            lod,
            passes,
            probe,
            options,
        })
    }

    /// The LOD stage's counters of the last frame.
    pub fn read_lod_stats(&self, gpu: &Gpu) -> Result<lod::LodStats> {
        self.lod.read_stats(gpu)
    }

    pub fn options(&self) -> &ParamPointsOptions {
        &self.options
    }

    /// The view of `camera` onto `scene` at `size` with this technique's supersampling.
    pub fn view(
        &self,
        scene: &GpuParamScene,
        camera: &OrbitCamera,
        size: (u32, u32),
    ) -> Result<View> {
        scene.view(camera, size, self.options.supersample)
    }

    /// [`Self::record`] with the LOD stage, the points and the resolve in timer scopes "lod",
    /// "points" and "resolve".
    #[allow(clippy::too_many_arguments)]
    pub fn record_timed(
        &self,
        rec: &Recorder,
        timer: &mut tessera_gpu::Timer,
        scene: &GpuParamScene,
        view: &View,
        frame: &PointsFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        timer.scope(rec, "lod", |rec| self.lod.record(rec, scene, view, None));
        self.record_draw(rec, Some(timer), scene, view, frame, pixels, background);
    }

    /// The points and the resolve of the patches the LOD stage left, each in its timer scope
    /// where a timer is given.
    #[allow(clippy::too_many_arguments)]
    fn record_draw(
        &self,
        rec: &Recorder,
        timer: Option<&mut tessera_gpu::Timer>,
        scene: &GpuParamScene,
        view: &View,
        frame: &PointsFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        let o = &self.options;
        let points = |rec: &Recorder| {
            let (footprint, density, max_side) = (o.footprint, o.density, o.max_side);
            let lod = &self.lod;
            self.passes
                .record_points(rec, lod, scene, view, frame, footprint, density, max_side)
        };
        let resolve = |rec: &Recorder| {
            let lod = &self.lod;
            self.passes
                .record_resolve(rec, lod, scene, view, frame, pixels, background)
        };
        match timer {
            Some(timer) => {
                timer.scope(rec, "points", points);
                timer.scope(rec, "resolve", resolve);
            }
            None => {
                points(rec);
                resolve(rec);
            }
        }
    }

    /// Records a whole frame (LOD, points, resolve) into `frame`, for benchmarks.
    pub fn record(
        &self,
        rec: &Recorder,
        scene: &GpuParamScene,
        view: &View,
        frame: &PointsFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        self.lod.record(rec, scene, view, None);
        self.record_draw(rec, None, scene, view, frame, pixels, background);
    }

    /// Renders `scene` from `camera` at `size` in front of `background`: the image and the GPU
    /// milliseconds of the frame. A frame that lost patches to full lists is an error.
    pub fn render_image(
        &self,
        gpu: &Gpu,
        scene: &GpuParamScene,
        camera: &OrbitCamera,
        size: (u32, u32),
        background: [f32; 3],
    ) -> Result<(RgbaImage, f64)> {
        let view = self.view(scene, camera, size)?;
        let frame = PointsFrame::new(gpu, &view)?;
        let pixels = Target::new(gpu, size.0, size.1)?;
        let info = self.render_frame(gpu, scene, &view, &frame, &pixels, background)?;
        Ok((pixels.read(gpu)?, info.gpu_ms))
    }

    /// Renders into `frame` and reports the frame's counters.
    pub fn render_frame(
        &self,
        gpu: &Gpu,
        scene: &GpuParamScene,
        view: &View,
        frame: &PointsFrame,
        pixels: &Target,
        background: [f32; 3],
    ) -> Result<ParamFrameInfo> {
        let raster = (frame.raster.width, frame.raster.height);
        if raster != view.raster_size() || (pixels.width, pixels.height) != view.size {
            return Err(Error::Invalid(format!(
                "param-points: a raster of {raster:?} and an image of {}x{} for a view of \
                 {:?}, raster {:?}",
                pixels.width,
                pixels.height,
                view.size,
                view.raster_size()
            )));
        }
        let gpu_ms = tessera_gpu::timing::time_once(gpu, "param-points", |rec| {
            self.record(rec, scene, view, frame, pixels, background);
            Ok::<(), Error>(())
        })?;
        let stats = self.lod.read_frame_stats(gpu, "param-points")?;
        Ok(ParamFrameInfo { gpu_ms, stats })
    }

    /// Runs the LOD stage alone; returns the patches to render (GPU order), the counters and,
    /// with `capture` > 0, up to that many of the samples the steps evaluated.
    pub fn run_lod(
        &self,
        gpu: &Gpu,
        scene: &GpuParamScene,
        view: &View,
        capture: u32,
    ) -> Result<(Vec<GpuPatch>, LodStats, Vec<LodSample>)> {
        let buffer = gpu.create_buffer(
            "param lod capture",
            SAMPLE_BYTES * u64::from(capture.max(1)),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
        )?;
        gpu.submit("param lod", |rec| {
            self.lod.record(rec, scene, view, Some((&buffer, capture)))
        })
        .map_err(Error::from)
        .and_then(|_| {
            let stats = self.lod.read_stats(gpu)?;
            let samples: Vec<LodSample> =
                gpu.read_elements(&buffer, stats.captured.min(capture) as usize)?;
            Ok((self.lod.read_patches(gpu)?, stats, samples))
        })
    }

    /// Fills the patch lists with all-ones words, so that tests catch slots never written.
    pub fn poison(&self, gpu: &Gpu) -> Result<()> {
        self.lod.poison(gpu)
    }

    /// Evaluates `(object, u, v)` triples on the GPU with the shaders' functions.
    pub fn probe(
        &self,
        gpu: &Gpu,
        scene: &GpuParamScene,
        points: &[(u32, f32, f32)],
    ) -> Result<Vec<ProbeResult>> {
        if let Some(p) = points.iter().find(|p| p.0 >= scene.object_count) {
            return Err(Error::Invalid(format!(
                "probe of object {} in a scene of {}",
                p.0, scene.object_count
            )));
        }
        let words: Vec<[u32; 4]> = points
            .iter()
            .map(|&(o, u, v)| [o, u.to_bits(), v.to_bits(), 0])
            .collect();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let input = gpu.upload_buffer("param probes", bytemuck::cast_slice(&words), usage)?;
        let bytes = (points.len().max(1) * std::mem::size_of::<ProbeResult>()) as u64;
        let output = gpu.create_buffer(
            "param probe results",
            bytes,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let [objects, values, table] = self.lod.scene_bindings(scene);
        let count = points.len() as u32;
        let result = gpu
            .submit("param probe", |rec| {
                rec.fill_buffer(&output, u32::MAX);
                rec.barrier();
                rec.dispatch(
                    &self.probe,
                    &[
                        objects,
                        values,
                        table,
                        Binding::Buffer(&input),
                        Binding::Buffer(&output),
                    ],
                    bytemuck::bytes_of(&count),
                    [count, 1, 1],
                );
            })
            .map_err(Error::from)
            .and_then(|_| Ok(gpu.read_elements::<ProbeResult>(&output, points.len())?));
        result
    }
}
