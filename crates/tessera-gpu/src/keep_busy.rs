//! Keeps the GPU loaded between timed benchmark frames.
//!
//! A benchmark submits a frame, waits for it, reads its timestamps and records the next one;
//! with frames under a millisecond the GPU idles most of the time, and a GPU that idles lowers
//! its clocks. On the H200 the SM clock fell from 1,980 MHz to 900–1,500 MHz within half a
//! second of such frames, and sub-millisecond cells read up to 2.7× slower, by an amount that
//! changed from process to process (docs/BENCHMARKS.md, runs 107–108). A continuous render loop,
//! which is what papers time, keeps the GPU busy. So after each frame's last timestamp the
//! harness records an arithmetic-only dispatch, sized from the frame's time so that frame and
//! dispatch take about `target_ms` together: the GPU stays loaded through the host's work
//! between submissions, and the timed scopes never include it (a barrier separates the two).

use crate::commands::{Binding, Recorder};
use crate::context::Gpu;
use crate::error::Result;
use crate::memory::{Buffer, MemoryLocation};
use crate::pipeline::{Pipeline, Slot};
use crate::shader::{ShaderCompiler, Source};
use crate::timer::Timer;
use ash::vk;
use bytemuck::{Pod, Zeroable};

/// Workgroups of the dispatch: enough to reach every multiprocessor of a large GPU, few enough
/// that one iteration of the loop is a small step.
pub const KEEP_BUSY_WORKGROUPS: u32 = 256;
/// Invocations per workgroup (`local_size_x` of `keep_busy.comp.glsl`).
pub const KEEP_BUSY_WORKGROUP_SIZE: u32 = 64;
/// The generator the dispatch steps (a linear congruential one: state × multiplier +
/// increment, modulo 2^32); the shader gets both as defines.
const GENERATOR_MULTIPLIER: u32 = 1_664_525;
const GENERATOR_INCREMENT: u32 = 1_013_904_223;
/// Iterations of the first dispatch, before any has been timed: short on any device.
const FIRST_ITERATIONS: u32 = 256;
/// How much longer than the last timed dispatch the next may be planned at most, so that one
/// short, noisy timing cannot plan a very long dispatch.
const MAX_GROWTH: f64 = 8.0;
/// Dispatches shorter than this (ms) are left out: they would not keep anything loaded.
const MIN_DISPATCH_MS: f64 = 0.02;
/// Timings shorter than this (ms) say too little about the rate to plan from.
const MIN_RATE_SAMPLE_MS: f64 = 0.005;

/// Push constants of `keep_busy.comp.glsl` (its `KeepBusyParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct KeepBusyParams {
    pub iterations: u32,
    pub seed: u32,
}

/// What the dispatch's workgroup `group` stores: the generator stepped `iterations` times from
/// the seed of its first invocation (the CPU twin of the shader, for tests).
pub fn last_state(params: KeepBusyParams, group: u32) -> u32 {
    let mut state = params.seed ^ (group * KEEP_BUSY_WORKGROUP_SIZE);
    for _ in 0..params.iterations {
        state = state
            .wrapping_mul(GENERATOR_MULTIPLIER)
            .wrapping_add(GENERATOR_INCREMENT);
    }
    state
}

/// Iterations for the next dispatch: enough to fill what `frame_ms` leaves of `target_ms` at
/// the rate the last timed dispatch ran (`iterations` in `dispatch_ms`), at most
/// [`MAX_GROWTH`] times those; 0 when the frame alone fills the target.
pub fn planned_iterations(target_ms: f64, frame_ms: f64, iterations: u32, dispatch_ms: f64) -> u32 {
    let fill_ms = target_ms - frame_ms;
    if fill_ms.is_nan() || fill_ms < MIN_DISPATCH_MS {
        return 0;
    }
    if dispatch_ms.is_nan() || dispatch_ms < MIN_RATE_SAMPLE_MS || iterations == 0 {
        // Nothing to plan from yet: grow from what ran.
        let base = f64::from(iterations.max(FIRST_ITERATIONS));
        return (base * MAX_GROWTH).min(f64::from(u32::MAX)) as u32;
    }
    let per_ms = f64::from(iterations) / dispatch_ms;
    let planned = (fill_ms * per_ms).min(f64::from(iterations) * MAX_GROWTH);
    planned.clamp(1.0, f64::from(u32::MAX)) as u32
}

/// The dispatch after each timed frame; inert (records nothing) with a target of 0.
pub struct KeepBusy {
    target_ms: f64,
    gpu_side: Option<(Pipeline, Buffer, Timer)>,
    /// Iterations the next dispatch runs (0: none).
    next_iterations: u32,
    /// The last dispatch recorded, and whether it is still to be timed.
    last: Option<KeepBusyParams>,
    pending: bool,
    /// The timed dispatch to plan from: its iterations and milliseconds.
    rate: Option<(u32, f64)>,
}

impl KeepBusy {
    /// Frames plus dispatches of about `target_ms` each; no dispatch at all for a target of 0
    /// or less.
    pub fn new(gpu: &Gpu, target_ms: f64) -> Result<KeepBusy> {
        let gpu_side = if target_ms > 0.0 {
            let source = Source::new(
                concat!(env!("CARGO_MANIFEST_DIR"), "/src/keep_busy.comp.glsl"),
                include_str!("keep_busy.comp.glsl"),
            );
            let defines = [
                ("WORKGROUP_SIZE", KEEP_BUSY_WORKGROUP_SIZE),
                ("GENERATOR_MULTIPLIER", GENERATOR_MULTIPLIER),
                ("GENERATOR_INCREMENT", GENERATOR_INCREMENT),
            ]
            .map(|(name, value)| (name.to_string(), format!("{value}u")));
            let spirv = ShaderCompiler::new().compile(&source, &defines)?;
            let pipeline = gpu.compute_pipeline("keep busy", &spirv, &[Slot::StorageBuffer])?;
            let sink = gpu.create_buffer(
                "keep busy",
                u64::from(KEEP_BUSY_WORKGROUPS) * 4,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )?;
            let mut timer = Timer::new(gpu, 1)?;
            timer.reset(gpu);
            Some((pipeline, sink, timer))
        } else {
            None
        };
        Ok(KeepBusy {
            target_ms,
            gpu_side,
            next_iterations: FIRST_ITERATIONS,
            last: None,
            pending: false,
            rate: None,
        })
    }

    /// Records the dispatch after a frame's commands (and after all of them have finished).
    pub fn record(&mut self, rec: &Recorder) {
        let Some((pipeline, sink, timer)) = &mut self.gpu_side else {
            return;
        };
        if self.next_iterations == 0 {
            return;
        }
        let params = KeepBusyParams {
            iterations: self.next_iterations,
            seed: self.last.map_or(1, |p| p.seed.wrapping_add(1)),
        };
        rec.barrier();
        timer.scope(rec, "keep busy", |rec| {
            rec.dispatch_groups(
                pipeline,
                &[Binding::Buffer(sink)],
                bytemuck::bytes_of(&params),
                [KEEP_BUSY_WORKGROUPS, 1, 1],
            )
        });
        self.last = Some(params);
        self.pending = true;
    }

    /// After the submission ran: times the dispatch and plans the next one for a frame of
    /// `frame_ms`.
    pub fn frame_done(&mut self, gpu: &Gpu, frame_ms: f64) -> Result<()> {
        let Some((_, _, timer)) = &mut self.gpu_side else {
            return Ok(());
        };
        if let (true, Some(last)) = (self.pending, self.last) {
            let dispatch_ms = timer.read_ms(gpu)?.first().map_or(0.0, |s| s.1);
            // A timing too short to plan from is kept only while there is nothing better.
            if dispatch_ms >= MIN_RATE_SAMPLE_MS
                || self.rate.is_none_or(|r| r.1 < MIN_RATE_SAMPLE_MS)
            {
                self.rate = Some((last.iterations, dispatch_ms));
            }
            self.pending = false;
            timer.reset(gpu);
        }
        self.next_iterations = match self.rate {
            None => FIRST_ITERATIONS,
            Some((iterations, ms)) => planned_iterations(self.target_ms, frame_ms, iterations, ms),
        };
        Ok(())
    }

    /// The last dispatch recorded and the buffer it stored into (tests compare it with
    /// [`last_state`]).
    pub fn last_dispatch(&self) -> Option<(KeepBusyParams, &Buffer)> {
        let (_, sink, _) = self.gpu_side.as_ref()?;
        Some((self.last?, sink))
    }

    /// Iterations the next dispatch will run (0: none).
    pub fn next_iterations(&self) -> u32 {
        self.next_iterations
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dispatch_fills_what_the_frame_leaves_at_the_measured_rate() {
        // 1,000 iterations took 0.5 ms: 1.5 ms left of 2 take 3,000.
        assert_eq!(planned_iterations(2.0, 0.5, 1000, 0.5), 3000);
        // Never more than eight times what was timed, however fast it looked.
        assert_eq!(planned_iterations(2.0, 0.0, 100, 0.01), 800);
        // A timing too short to trust: grow eightfold from what ran.
        assert_eq!(planned_iterations(2.0, 0.1, 256, 0.001), 2048);
        assert_eq!(planned_iterations(2.0, 0.1, 0, 0.0), FIRST_ITERATIONS * 8);
        // The frame fills the target (or nearly, or its time is unknown): none.
        assert_eq!(planned_iterations(2.0, 2.5, 1000, 0.5), 0);
        assert_eq!(planned_iterations(2.0, 1.99, 1000, 0.5), 0);
        assert_eq!(planned_iterations(2.0, f64::NAN, 1000, 0.5), 0);
        assert_eq!(planned_iterations(0.0, 0.0, 1000, 0.5), 0);
    }

    #[test]
    fn the_cpu_twin_steps_the_generator_from_each_groups_first_seed() {
        let params = KeepBusyParams {
            iterations: 2,
            seed: 5,
        };
        let step = |s: u32| s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        assert_eq!(last_state(params, 0), step(step(5)));
        assert_eq!(last_state(params, 3), step(step(5 ^ 192)));
    }
}
