//! Timed frames of renderers behind the front door: what every technique scenario shares.
//!
//! One rule sizes the buffers a frame fills (triangle lists, tile lists): the renderer grows
//! them itself when a frame overflows ([`Renderer::finish_frame`]). A scenario therefore
//! renders each distinct frame once untimed ("settling"), so that timed frames find every
//! buffer large enough; a timed frame that still overflows is an error, not a silent
//! truncation.

use super::{FramePlan, StageStats};
use crate::error::{Error, Result};
use crate::renderer::{FrameOutcome, Renderer, Target, MAX_TIMER_SCOPES};
use tessera_data::{OrbitCamera, View};
use tessera_gpu::timing::{frame_loop, TimedFrame, TimedFrames};
use tessera_gpu::{Gpu, Recorder, Timer};

/// Sets frame `k`'s look on the renderer before it is recorded (an isovalue sweep); `None`
/// keeps the look fixed.
pub(super) type EachFrame<'a> = Option<&'a dyn Fn(u32, &mut dyn Renderer) -> Result<()>>;

/// The stage that sums a frame's stages when it has several.
pub(super) const FRAME_STAGE: &str = "frame";
/// The stage that spans a frame of several stages, first start to last end: its whole time,
/// with whatever runs between the stages, which [`FRAME_STAGE`] leaves out.
pub(super) const FRAME_SPAN_STAGE: &str = "frame-span";

/// Statistics per scope (by position), then, when a frame has several scopes, of their sum
/// as [`FRAME_STAGE`] (the stages follow each other) and of the frame's span as
/// [`FRAME_SPAN_STAGE`].
fn stage_stats(timed: &TimedFrames) -> Vec<StageStats> {
    let mut stages = timed.scope_stats();
    if stages.len() > 1 {
        stages.push(timed.sum_stats(FRAME_STAGE));
        stages.push(timed.span_stats(FRAME_SPAN_STAGE));
    }
    stages
}

/// The error for a timed frame that overflowed although settling sized its buffers.
fn overflowed(renderer: &dyn Renderer) -> Error {
    Error::Invalid(format!(
        "{}: a timed frame overflowed its buffers after settling",
        renderer.technique().name()
    ))
}

struct MonoFrames<'a> {
    renderer: &'a mut dyn Renderer,
    view: &'a View,
    target: &'a Target,
    each_frame: EachFrame<'a>,
    /// The frame being recorded (its look is set).
    frame: u32,
}

impl TimedFrame for MonoFrames<'_> {
    type Error = Error;

    fn record(&mut self, rec: &Recorder, timer: &mut Timer) -> Result<()> {
        self.renderer.record(rec, self.view, self.target, timer)
    }

    fn finish(&mut self, gpu: &Gpu) -> Result<()> {
        if self.renderer.finish_frame(gpu)? == FrameOutcome::Retry {
            return Err(overflowed(self.renderer));
        }
        // The next frame's look is set between submissions, as a user's slider would.
        self.frame += 1;
        match self.each_frame {
            Some(each) => each(self.frame, &mut *self.renderer),
            None => Ok(()),
        }
    }
}

/// Renders `frames` frames of `view` untimed (frame k with its look), growing buffers as
/// frames overflow, so that timed frames find them large enough.
fn settle_frames(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    view: &View,
    frames: u32,
    each_frame: EachFrame,
) -> Result<()> {
    let mut frame = crate::renderer::Frame::new(gpu, view.size)?;
    for k in 0..frames {
        if let Some(each) = each_frame {
            each(k, renderer)?;
        }
        frame.render(gpu, renderer, view)?;
    }
    if let Some(each) = each_frame {
        each(0, renderer)?;
    }
    Ok(())
}

/// Times `plan` frames that `record` records, for scenarios driven below the front door.
/// Stages are its scopes, and their sum as [`FRAME_STAGE`] when there are several.
pub(super) fn time_recorded(
    gpu: &Gpu,
    plan: FramePlan,
    record: impl FnMut(&Recorder, &mut Timer) -> Result<()>,
) -> Result<Vec<StageStats>> {
    struct Recorded<R>(R);
    impl<R: FnMut(&Recorder, &mut Timer) -> Result<()>> TimedFrame for Recorded<R> {
        type Error = Error;
        fn record(&mut self, rec: &Recorder, timer: &mut Timer) -> Result<()> {
            (self.0)(rec, timer)
        }
    }
    let frames = frame_loop(gpu, plan, MAX_TIMER_SCOPES, &mut Recorded(record))?;
    Ok(stage_stats(&frames))
}

/// Times `plan` frames of `view` after settling on the first `distinct` frames' looks.
/// Stages are the renderer's scopes, and their sum as [`FRAME_STAGE`] when there are several.
pub(super) fn time_mono(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    view: &View,
    plan: FramePlan,
    distinct: u32,
    each_frame: EachFrame,
) -> Result<Vec<StageStats>> {
    let frames = mono_frames(gpu, renderer, view, plan, distinct, each_frame)?;
    Ok(stage_stats(&frames))
}

/// Times one frame of `view` as a whole (all its stages summed) under `name`.
pub(super) fn time_mono_total(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    view: &View,
    plan: FramePlan,
    name: &str,
) -> Result<StageStats> {
    let frames = mono_frames(gpu, renderer, view, plan, 1, None)?;
    Ok(frames.sum_stats(name))
}

fn mono_frames(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    view: &View,
    plan: FramePlan,
    distinct: u32,
    each_frame: EachFrame,
) -> Result<TimedFrames> {
    settle_frames(gpu, renderer, view, distinct.max(1), each_frame)?;
    renderer.prepare_frame(gpu, view)?;
    let target = Target::new(gpu, view.size.0, view.size.1)?;
    let mut timed = MonoFrames {
        renderer,
        view,
        target: &target,
        each_frame,
        frame: 0,
    };
    frame_loop(gpu, plan, MAX_TIMER_SCOPES, &mut timed)
}

/// How a stereo pair is drawn.
pub(super) enum Pair<'a> {
    /// In one pass by a renderer whose `prepare_stereo` said so (multiview, re-projection).
    OnePass(&'a mut dyn Renderer),
    /// As two frames by one renderer that carries no state between frames (ray marching).
    OneRendererTwoFrames(&'a mut dyn Renderer),
    /// As two frames, each eye by its own renderer (its own culling state).
    TwoFrames([&'a mut dyn Renderer; 2]),
}

struct StereoFrames<'p, 'a> {
    pair: Pair<'p>,
    eyes: &'a [View; 2],
    targets: [&'a Target; 2],
}

impl TimedFrame for StereoFrames<'_, '_> {
    type Error = Error;

    fn record(&mut self, rec: &Recorder, timer: &mut Timer) -> Result<()> {
        match &mut self.pair {
            Pair::OnePass(r) => r.record_stereo(rec, self.eyes, self.targets, timer),
            Pair::OneRendererTwoFrames(r) => {
                (0..2).try_for_each(|e| r.record(rec, &self.eyes[e], self.targets[e], timer))
            }
            Pair::TwoFrames(rs) => {
                (0..2).try_for_each(|e| rs[e].record(rec, &self.eyes[e], self.targets[e], timer))
            }
        }
    }

    fn finish(&mut self, gpu: &Gpu) -> Result<()> {
        let renderers: Vec<&mut dyn Renderer> = match &mut self.pair {
            Pair::OnePass(r) | Pair::OneRendererTwoFrames(r) => vec![&mut **r],
            Pair::TwoFrames([a, b]) => vec![&mut **a, &mut **b],
        };
        for r in renderers {
            if r.finish_frame(gpu)? == FrameOutcome::Retry {
                return Err(overflowed(r));
            }
        }
        Ok(())
    }
}

/// Times `plan` stereo pairs of `eyes`, all stages of a pair summed under `name`. A one-pass
/// renderer must have said yes to `prepare_stereo` for these eyes.
pub(super) fn time_stereo(
    gpu: &Gpu,
    mut pair: Pair,
    eyes: &[View; 2],
    plan: FramePlan,
    name: &str,
) -> Result<StageStats> {
    let (w, h) = eyes[0].size;
    let targets = [Target::new(gpu, w, h)?, Target::new(gpu, w, h)?];
    // Settle: one pair recorded and finished untimed (buffers grown where it overflowed).
    match &mut pair {
        Pair::OnePass(r) => {
            let mut left = crate::renderer::Frame::new(gpu, (w, h))?;
            let mut right = crate::renderer::Frame::new(gpu, (w, h))?;
            crate::renderer::render_stereo(gpu, &mut **r, eyes, &mut left, &mut right)?;
            r.prepare_stereo(gpu, eyes)?;
        }
        Pair::OneRendererTwoFrames(r) => {
            settle_frames(gpu, &mut **r, &eyes[0], 1, None)?;
            r.prepare_frame(gpu, &eyes[0])?;
        }
        Pair::TwoFrames(rs) => {
            for (r, eye) in rs.iter_mut().zip(eyes) {
                settle_frames(gpu, &mut **r, eye, 1, None)?;
                r.prepare_frame(gpu, eye)?;
            }
        }
    }
    let mut timed = StereoFrames {
        pair,
        eyes,
        targets: [&targets[0], &targets[1]],
    };
    Ok(frame_loop(gpu, plan, MAX_TIMER_SCOPES, &mut timed)?.sum_stats(name))
}

/// Renders for a while right after data arrives on the GPU. Measured on the H200: with only
/// the per-measurement warm-up, the first size timed after uploading a 2 GiB volume came out
/// 2–4× slower than the same size timed later (docs/BENCHMARKS.md, run 16). `quick` runs (CPU
/// devices, smoke tests) render one small frame.
pub(super) fn settle_after_upload(
    gpu: &Gpu,
    renderer: &mut dyn Renderer,
    quick: bool,
) -> Result<()> {
    let (frames, size) = if quick {
        (1, (64, 64))
    } else {
        (100, (1280, 720))
    };
    let view = renderer.view(&OrbitCamera::default(), size)?;
    settle_frames(gpu, renderer, &view, 1, None)?;
    let target = Target::new(gpu, size.0, size.1)?;
    let mut timer = Timer::new(gpu, frames * MAX_TIMER_SCOPES)?;
    timer.reset(gpu);
    let mut recorded = Ok(());
    gpu.submit("settle", |rec| {
        recorded = (0..frames).try_for_each(|_| renderer.record(rec, &view, &target, &mut timer));
    })?;
    recorded?;
    renderer.finish_frame(gpu)?;
    Ok(())
}
