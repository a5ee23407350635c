//! The front door: every technique behind one trait, so that the CLI, the benchmarks, the tests
//! and the examples (and a viewer or Python after them) drive them alike.
//!
//! How a frame flows:
//! 1. [`create`] builds a renderer for a [`Technique`] and [`RendererOptions`] (the path is
//!    chosen here, from the device and the options).
//! 2. [`Renderer::set_data`] takes a [`Dataset`] once: uploads, auxiliary structures (the
//!    min-max octree, the glyph grid), pipelines that depend on the data (sample type, a user
//!    function). Nothing else uploads data.
//! 3. [`Renderer::set_appearance`] takes an [`Appearance`] whenever the look changes: isovalue,
//!    transfer function, background. These become push constants or small buffer writes. Set
//!    the first look before the data: pipelines that depend on both (interval shading's
//!    integrand kind) are then built once.
//! 4. Per frame, with a [`View`] made by [`Renderer::view`]: [`Renderer::prepare_frame`] makes
//!    the buffers that depend on the image size (once per size), [`Renderer::record`] records
//!    the frame into the caller's command buffer and [`Target`], the caller submits, and
//!    [`Renderer::finish_frame`] reads the frame's counters (and asks for the frame again when
//!    a buffer overflowed and was grown). Culling state carries over from frame to frame.
//! 5. The image stays on the GPU in the [`Target`] until someone reads it back; a technique
//!    that accumulates a float quantity before turning it into colour (interval shading's
//!    optical depth) also gives that quantity ([`Renderer::accumulated`]).
//!
//! [`Frame`] does steps 4–5 for callers that just want images and times.

mod interval;
mod iso;
mod meshlets;
mod param;
mod pmb;
mod shell;
mod surface_frame;
mod technique;

use crate::error::{Error, Result};
pub use crate::iso::direct::compute::DirectRaster;
pub use crate::iso::HiddenSide;
use crate::path::Path;
pub use crate::target::Target;
pub use crate::tet::interval::{ComputeScheme, IntervalTuning, SubgroupDraw};
use std::collections::BTreeMap;
pub use technique::{path_for, Culling, RendererOptions, Technique, OPTION_NAMES};
pub use tessera_data::mc_ambiguity::AmbiguityRule;
pub use tessera_data::pmb::PmbBlockSize;
use tessera_data::scene::{Appearance, Dataset};
pub use tessera_data::tet::shell::{AmbientOcclusion, LayoutKind, Light};
use tessera_data::{DepthFit, OrbitCamera, RgbaImage, View};
use tessera_gpu::{Gpu, Recorder, ScopeTimes, Timer};

/// Timer scopes one frame may open.
pub const MAX_TIMER_SCOPES: u32 = 8;
/// Times a frame is rendered again after buffers overflowed and were grown.
const MAX_RETRIES: u32 = 2;

/// What the last frame did, where a technique counts it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameStats {
    /// Triangles rasterized (isosurface techniques).
    pub triangles: Option<u64>,
    /// Blocks drawn, with occlusion culling: (drawn from last frame's visible set, newly
    /// visible ones).
    pub blocks_drawn: Option<(u64, u64)>,
    /// Patches the LOD stage handed to drawing (parametric techniques).
    pub patches: Option<u64>,
    /// Tets clipped at the near plane (interval shading).
    pub tets_clipped: Option<u64>,
    /// Further counters of the technique's passes, by name (benchmarks record them).
    pub details: BTreeMap<&'static str, u64>,
}

/// Work a renderer did on the data side, so callers (and tests) can see that an appearance
/// change uploaded nothing and rebuilt nothing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WorkCounters {
    /// Data sets uploaded ([`Renderer::set_data`]).
    pub data_uploads: u64,
    /// Bytes uploaded with them.
    pub data_bytes: u64,
    /// Times the pipelines were built.
    pub pipeline_builds: u64,
}

/// Whether a recorded frame is complete.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameOutcome {
    Done,
    /// A buffer overflowed; it was grown and the frame must be recorded again.
    Retry,
}

/// What a technique accumulated per pixel before turning it into colour
/// ([`Renderer::accumulated`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Accumulation {
    pub width: u32,
    pub height: u32,
    /// Per pixel, rows top to bottom.
    pub values: Vec<[f32; 3]>,
    /// What the values are, as [`Accumulation::quantity_name`] names it.
    pub quantity: AccumulatedQuantity,
}

/// The kind of float quantity an [`Accumulation`] holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccumulatedQuantity {
    /// Optical depth per colour channel: the background shows through as `exp(-depth)`.
    OpticalDepth,
    /// Emitted light per channel, added to the background.
    Emission,
    /// `[largest scalar mapped to [0, 1], coverage (> 0 where a tet was crossed), 0]`.
    Maximum,
    /// The light reaching the eye per channel (emission composited front to back over the
    /// background), before it is clamped to [0, 1] and quantized to 8 bits.
    Radiance,
}

impl Accumulation {
    pub fn quantity_name(&self) -> &'static str {
        match self.quantity {
            AccumulatedQuantity::OpticalDepth => "optical-depth",
            AccumulatedQuantity::Emission => "emission",
            AccumulatedQuantity::Maximum => "maximum",
            AccumulatedQuantity::Radiance => "radiance",
        }
    }
}

/// One technique behind the front door (see the module documentation for the order of calls).
pub trait Renderer: Send {
    fn technique(&self) -> Technique;
    fn path(&self) -> Path;
    /// Uploads `data` and builds what the technique needs of it; data of another kind than
    /// the technique draws is refused.
    fn set_data(&mut self, gpu: &Gpu, data: &Dataset) -> Result<()>;
    /// Changes the look without uploading data or building pipelines.
    fn set_appearance(&mut self, gpu: &Gpu, look: &Appearance) -> Result<()>;
    /// What the view's depth range is fitted to (the data's bounds).
    fn depth_fit(&self) -> DepthFit<'_> {
        DepthFit::UnitBox
    }
    /// Raster samples per pixel along each axis.
    fn supersample(&self) -> u32 {
        1
    }
    /// Makes the buffers `view`'s sizes need; nothing when they exist.
    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()>;
    /// Records a frame of `view` into `target` (of the view's image size), timing its stages
    /// in `timer`. Several frames may be recorded before one [`Renderer::finish_frame`] (a
    /// warm-up submits many at once).
    fn record(
        &mut self,
        rec: &Recorder,
        view: &View,
        target: &Target,
        timer: &mut Timer,
    ) -> Result<()>;
    /// Makes the buffers a stereo pair of `eyes` needs where the technique draws both eyes
    /// more cheaply than two frames (re-projecting one extraction, paper D's stereo); `false`
    /// when it has no such way, and the caller renders the eyes as two frames.
    fn prepare_stereo(&mut self, _gpu: &Gpu, _eyes: &[View; 2]) -> Result<bool> {
        Ok(false)
    }
    /// Records both eyes into `targets` after [`Renderer::prepare_stereo`] said `true`.
    fn record_stereo(
        &mut self,
        _rec: &Recorder,
        _eyes: &[View; 2],
        _targets: [&Target; 2],
        _timer: &mut Timer,
    ) -> Result<()> {
        Err(Error::Invalid(format!(
            "{}: no stereo path (render the eyes as two frames)",
            self.technique().name()
        )))
    }
    /// Reads the counters of the frame (or stereo pair) just submitted.
    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome>;
    fn stats(&self) -> FrameStats;
    fn counters(&self) -> WorkCounters;
    /// Reads back the float quantity the last frame accumulated before its colour was made
    /// from it; `None` for techniques that draw colour directly.
    fn accumulated(&self, _gpu: &Gpu) -> Result<Option<Accumulation>> {
        Ok(None)
    }

    /// The view of `camera` over an image of `size` pixels for this renderer's data.
    fn view(&self, camera: &OrbitCamera, size: (u32, u32)) -> Result<View> {
        Ok(View::new(
            camera,
            size,
            self.supersample(),
            self.depth_fit(),
        )?)
    }
}

/// A renderer of `technique` on `gpu`.
pub fn create(
    gpu: &Gpu,
    technique: Technique,
    options: &RendererOptions,
) -> Result<Box<dyn Renderer>> {
    Ok(match technique {
        Technique::Raymarch | Technique::Direct => {
            Box::new(iso::IsoRenderer::new(gpu, technique, options)?)
        }
        Technique::Meshlets | Technique::Offline => {
            Box::new(meshlets::MeshletRenderer::new(gpu, technique, options)?)
        }
        Technique::Pmb => Box::new(pmb::PmbRenderer::new(gpu, options)?),
        Technique::Interval => Box::new(interval::IntervalRenderer::new(gpu, options)?),
        Technique::Shell => Box::new(shell::ShellRenderer::new(gpu, options)?),
        Technique::ParamPoints | Technique::ParamTess | Technique::ShRaytrace => {
            Box::new(param::ParamRenderer::new(gpu, technique, options)?)
        }
    })
}

/// A renderer of `technique` with its first look and its data set, in the order that builds
/// the pipelines once (see the module documentation).
pub fn create_for(
    gpu: &Gpu,
    technique: Technique,
    options: &RendererOptions,
    look: &Appearance,
    data: &Dataset,
) -> Result<Box<dyn Renderer>> {
    let mut renderer = create(gpu, technique, options)?;
    renderer.set_appearance(gpu, look)?;
    renderer.set_data(gpu, data)?;
    Ok(renderer)
}

/// A target and a timer kept from frame to frame: rendering N frames allocates nothing per
/// frame once the renderer's buffers exist.
pub struct Frame {
    pub target: Target,
    timer: Timer,
}

/// GPU milliseconds of one frame: per timer scope in recording order, and the whole frame
/// from the first scope's start to the last one's end.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameTimes {
    pub scopes: Vec<(String, f64)>,
    /// The whole frame, what runs between its scopes included: at least their sum.
    pub span_ms: f64,
}

impl FrameTimes {
    /// The whole frame's GPU time (its span), what a render loop pays.
    pub fn total_ms(&self) -> f64 {
        self.span_ms
    }

    /// The passes' own times added up, without the gaps between them.
    pub fn passes_ms(&self) -> f64 {
        self.scopes.iter().map(|s| s.1).sum()
    }
}

impl From<ScopeTimes> for FrameTimes {
    fn from(times: ScopeTimes) -> FrameTimes {
        FrameTimes {
            scopes: times.scopes,
            span_ms: times.span_ms,
        }
    }
}

impl Frame {
    pub fn new(gpu: &Gpu, size: (u32, u32)) -> Result<Frame> {
        Ok(Frame {
            target: Target::new(gpu, size.0, size.1)?,
            timer: Timer::new(gpu, MAX_TIMER_SCOPES)?,
        })
    }

    /// Renders `view` into the target: records, submits, waits, and renders again (at most
    /// twice) when the renderer grew an overflowing buffer.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        renderer: &mut dyn Renderer,
        view: &View,
    ) -> Result<FrameTimes> {
        if view.size != (self.target.width, self.target.height) {
            return Err(Error::Invalid(format!(
                "a {}x{} view for a {}x{} target",
                view.size.0, view.size.1, self.target.width, self.target.height
            )));
        }
        for _ in 0..=MAX_RETRIES {
            renderer.prepare_frame(gpu, view)?;
            self.timer.reset(gpu);
            let mut recorded = Ok(());
            let timer = &mut self.timer;
            let target = &self.target;
            gpu.submit(renderer.technique().name(), |rec| {
                recorded = renderer.record(rec, view, target, timer);
            })?;
            recorded?;
            if renderer.finish_frame(gpu)? == FrameOutcome::Done {
                return Ok(self.timer.read(gpu)?.into());
            }
        }
        Err(Error::Invalid(format!(
            "{}: the frame still overflowed after {MAX_RETRIES} larger tries",
            renderer.technique().name()
        )))
    }
}

/// Renders the two eyes of a stereo pair into `left` and `right`: in one pass where the
/// renderer has a stereo path, else as two frames. Returns the GPU times of all passes.
pub fn render_stereo(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    eyes: &[View; 2],
    left: &mut Frame,
    right: &mut Frame,
) -> Result<FrameTimes> {
    for (eye, frame) in eyes.iter().zip([&*left, &*right]) {
        if eye.size != (frame.target.width, frame.target.height) {
            return Err(Error::Invalid(format!(
                "a {}x{} eye for a {}x{} target",
                eye.size.0, eye.size.1, frame.target.width, frame.target.height
            )));
        }
    }
    for _ in 0..=MAX_RETRIES {
        if !renderer.prepare_stereo(gpu, eyes)? {
            let mut times = left.render(gpu, renderer, &eyes[0])?;
            let right_times = right.render(gpu, renderer, &eyes[1])?;
            times.scopes.extend(right_times.scopes);
            times.span_ms += right_times.span_ms;
            return Ok(times);
        }
        left.timer.reset(gpu);
        let mut recorded = Ok(());
        let (timer, targets) = (&mut left.timer, [&left.target, &right.target]);
        gpu.submit(renderer.technique().name(), |rec| {
            recorded = renderer.record_stereo(rec, eyes, targets, timer);
        })?;
        recorded?;
        if renderer.finish_frame(gpu)? == FrameOutcome::Done {
            return Ok(left.timer.read(gpu)?.into());
        }
    }
    Err(Error::Invalid(format!(
        "{}: the stereo pair still overflowed after {MAX_RETRIES} larger tries",
        renderer.technique().name()
    )))
}

/// One image with its GPU time and counters.
pub struct RenderedImage {
    pub image: RgbaImage,
    pub times: FrameTimes,
    pub stats: FrameStats,
}

/// Renders one image of `camera` at `size`: for single images (tests, `tessera render`);
/// interactive callers keep a [`Frame`].
pub fn render_image(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    camera: &OrbitCamera,
    size: (u32, u32),
) -> Result<RenderedImage> {
    let view = renderer.view(camera, size)?;
    let mut frame = Frame::new(gpu, size)?;
    let times = frame.render(gpu, renderer, &view)?;
    Ok(RenderedImage {
        image: frame.target.read(gpu)?,
        times,
        stats: renderer.stats(),
    })
}

/// The error for data of the wrong kind handed to a renderer.
pub(crate) fn wrong_data(technique: Technique, data: &Dataset) -> Error {
    Error::Invalid(format!(
        "{}: technique '{}' draws {}, not {}",
        data.name(),
        technique.name(),
        technique.draws().describe(),
        data.kind().describe()
    ))
}

/// The error for a frame recorded before `set_data`.
pub(crate) fn no_data(technique: Technique) -> Error {
    Error::Invalid(format!(
        "{}: a frame was asked for before any data was set",
        technique.name()
    ))
}
