//! GPU timing of whole frames: many frames per stage with statistics (benchmarks), or one
//! frame timed as a whole (single renders), and reading small counter buffers.

use crate::commands::Recorder;
use crate::context::Gpu;
use crate::error::{GpuError, Result};
use crate::keep_busy::KeepBusy;
use crate::timer::Timer;
use serde::Serialize;
use std::time::{Duration, Instant};

/// Frame counts for one measurement.
#[derive(Debug, Clone, Copy)]
pub struct FramePlan {
    /// Warm-up frames at least.
    pub warmup: u32,
    pub frames: u32,
    /// Warm-up frames at most: past `warmup`, frames keep warming up until their time settles
    /// ([`WarmUp`]) or this many ran. At or below `warmup`: exactly `warmup` frames.
    pub max_warmup: u32,
    /// Milliseconds of wall time the warm-up lasts at least (unless `max_warmup` frames ran
    /// first): on the H200 a glyph field's first cell ran 2–3.7× slow in all its passes through
    /// its warm-up and most of its timed frames, steadily enough to pass the settling test
    /// (docs/BENCHMARKS.md, runs 66–67).
    pub min_warmup_ms: u32,
    /// GPU milliseconds that each frame plus the arithmetic dispatch after it take (0: no
    /// dispatch): keeps the GPU loaded between frames, as a continuous render loop does, so
    /// that its clocks stay up ([`KeepBusy`]).
    pub keep_busy_ms: f64,
    /// Frames in one period of a scene whose frames differ on purpose (a time series of four
    /// steps: 4); the warm-up judges whole periods ([`WarmUp`]). 1 for a fixed scene.
    pub frames_per_cycle: u32,
}

impl Default for FramePlan {
    fn default() -> Self {
        FramePlan {
            warmup: 10,
            frames: 100,
            max_warmup: 200,
            min_warmup_ms: 500,
            keep_busy_ms: 2.0,
            frames_per_cycle: 1,
        }
    }
}

/// Frames in each of the two windows whose medians [`WarmUp`] compares.
pub const SETTLE_WINDOW: usize = 8;
/// How close (relative) the two windows' medians must be for the frame time to count as settled.
pub const SETTLE_TOLERANCE: f64 = 0.02;
/// How far (relative) above its median the slowest frame of the last window may be for the
/// frame time to count as settled.
pub const SETTLE_SPREAD: f64 = 0.15;

/// Decides when a measurement's warm-up is over: after at least `plan.warmup` frames, once the
/// median time of the last [`SETTLE_WINDOW`] frames is within [`SETTLE_TOLERANCE`] of the
/// median of the window before (clocks ramped, caches and lazily built pipelines warm), no
/// frame of the last window is more than [`SETTLE_SPREAD`] above its median, and
/// `plan.min_warmup_ms` have passed since the first frame; or after `plan.max_warmup` frames.
/// A stable median is not enough: on the H200 a scene's first cell was timed with many of its
/// frames twice as slow, in all its passes alike (docs/BENCHMARKS.md, run 66).
///
/// Where the frames cycle through different content (`plan.frames_per_cycle` > 1), the rules
/// apply to each whole cycle's time instead of each frame's: a time series whose steps take
/// 0.35 and 0.72 ms never met the spread rule frame by frame, though every cycle took the same
/// (docs/BENCHMARKS.md, run 111).
pub struct WarmUp {
    plan: FramePlan,
    frames: u32,
    /// The time of each whole cycle so far, and of the cycle under way.
    cycle_ms: Vec<f64>,
    running_ms: f64,
    started: Option<Instant>,
}

impl WarmUp {
    pub fn new(plan: FramePlan) -> WarmUp {
        WarmUp {
            plan,
            frames: 0,
            cycle_ms: Vec::new(),
            running_ms: 0.0,
            started: None,
        }
    }

    /// Whether the next frame is still a warm-up frame.
    pub fn warming(&self) -> bool {
        if self.frames < self.plan.warmup {
            return true;
        }
        self.frames < self.plan.max_warmup && !self.settled()
    }

    /// Whether the frames so far meet the settling rules (the two windows, the spread, the wall
    /// time), whatever the frame counts: false when the warm-up ended at `plan.max_warmup`
    /// unsettled, so that a measurement can say its frames may still have been moving.
    pub fn settled(&self) -> bool {
        let min_wall = Duration::from_millis(u64::from(self.plan.min_warmup_ms));
        if self.started.is_none_or(|t| t.elapsed() < min_wall) {
            return false;
        }
        let n = self.cycle_ms.len();
        if n < 2 * SETTLE_WINDOW || !self.frames.is_multiple_of(self.cycle()) {
            return false;
        }
        let last_window = &self.cycle_ms[n - SETTLE_WINDOW..];
        let last = median(last_window);
        let before = median(&self.cycle_ms[n - 2 * SETTLE_WINDOW..n - SETTLE_WINDOW]);
        let slowest = last_window.iter().copied().fold(f64::MIN, f64::max);
        let moving = (last - before).abs() > SETTLE_TOLERANCE * before.abs().max(f64::MIN_POSITIVE);
        !(moving || slowest > (1.0 + SETTLE_SPREAD) * last)
    }

    /// Records a warm-up frame's GPU time (all its scopes).
    pub fn add(&mut self, frame_ms: f64) {
        self.started.get_or_insert_with(Instant::now);
        self.frames += 1;
        self.running_ms += frame_ms;
        if self.frames.is_multiple_of(self.cycle()) {
            self.cycle_ms.push(self.running_ms);
            self.running_ms = 0.0;
        }
    }

    /// Warm-up frames run so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    fn cycle(&self) -> u32 {
        self.plan.frames_per_cycle.max(1)
    }
}

fn median(samples: &[f64]) -> f64 {
    let mut s = samples.to_vec();
    s.sort_by(f64::total_cmp);
    match s.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => s[n / 2],
        n => 0.5 * (s[n / 2 - 1] + s[n / 2]),
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct StageStats {
    pub stage: String,
    pub median_ms: f64,
    pub min_ms: f64,
    pub max_ms: f64,
    /// Warm-up frames the measurement ran before its timed frames ([`WarmUp`]).
    pub warmup_frames: u32,
    /// Whether that warm-up ended settled ([`WarmUp::settled`]); false where it ran into its
    /// frame limit first, or where there was none.
    pub settled: bool,
}

impl StageStats {
    pub fn from_samples(stage: &str, samples: &[f64]) -> StageStats {
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        StageStats {
            stage: stage.to_string(),
            median_ms: median(&s),
            min_ms: s.first().copied().unwrap_or(f64::NAN),
            max_ms: s.last().copied().unwrap_or(f64::NAN),
            warmup_frames: 0,
            settled: false,
        }
    }

    /// The same statistics, noted as measured after `warm_up`'s frames.
    pub fn after_warmup(self, warm_up: &WarmUp) -> StageStats {
        StageStats {
            warmup_frames: warm_up.frames(),
            settled: warm_up.settled(),
            ..self
        }
    }
}

/// One kind of timed frame for [`frame_loop`]: how a frame is recorded, its stages in timer
/// scopes, and what runs once its submission has completed, before its timestamps are read.
pub trait TimedFrame {
    type Error: From<GpuError>;
    fn record(&mut self, rec: &Recorder, timer: &mut Timer)
        -> std::result::Result<(), Self::Error>;
    fn finish(&mut self, _gpu: &Gpu) -> std::result::Result<(), Self::Error> {
        Ok(())
    }
}

/// The frames a [`frame_loop`] timed (per frame, its scopes' GPU milliseconds in recording
/// order, and its span: [`crate::timer::ScopeTimes`]) and the warm-up run before them.
pub struct TimedFrames {
    pub frames: Vec<Vec<(String, f64)>>,
    pub spans: Vec<f64>,
    pub warm_up: WarmUp,
}

impl TimedFrames {
    /// Statistics of each scope, by position (named as the first frame that has it names it;
    /// a frame with fewer scopes adds no sample to the ones it lacks).
    pub fn scope_stats(&self) -> Vec<StageStats> {
        let scopes = self.frames.iter().map(Vec::len).max().unwrap_or(0);
        (0..scopes)
            .map(|i| {
                let samples: Vec<&(String, f64)> =
                    self.frames.iter().filter_map(|f| f.get(i)).collect();
                let times: Vec<f64> = samples.iter().map(|s| s.1).collect();
                StageStats::from_samples(&samples[0].0, &times).after_warmup(&self.warm_up)
            })
            .collect()
    }

    /// Statistics of each frame's scopes summed, as one stage `name`.
    pub fn sum_stats(&self, name: &str) -> StageStats {
        let totals: Vec<f64> = self
            .frames
            .iter()
            .map(|f| f.iter().map(|s| s.1).sum())
            .collect();
        StageStats::from_samples(name, &totals).after_warmup(&self.warm_up)
    }

    /// Statistics of each frame's span, first scope's start to last scope's end, as one stage
    /// `name`: the frame's whole time, where the sum of its scopes leaves out what runs
    /// between them.
    pub fn span_stats(&self, name: &str) -> StageStats {
        StageStats::from_samples(name, &self.spans).after_warmup(&self.warm_up)
    }
}

/// Submits warm-up frames until [`WarmUp`] says they settled, then `plan.frames` timed frames,
/// each recorded by `timed` with at most `max_scopes` timer scopes and followed by
/// [`KeepBusy`]'s dispatch, outside its scopes.
pub fn frame_loop<F: TimedFrame + ?Sized>(
    gpu: &Gpu,
    plan: FramePlan,
    max_scopes: u32,
    timed: &mut F,
) -> std::result::Result<TimedFrames, F::Error> {
    let mut timer = Timer::new(gpu, max_scopes)?;
    let mut keep_busy = KeepBusy::new(gpu, plan.keep_busy_ms)?;
    let mut frames = Vec::with_capacity(plan.frames as usize);
    let mut spans = Vec::with_capacity(plan.frames as usize);
    let mut warm_up = WarmUp::new(plan);
    while frames.len() < plan.frames as usize {
        timer.reset(gpu);
        let mut recorded = Ok(());
        gpu.submit("benchmark frame", |rec| {
            recorded = timed.record(rec, &mut timer);
            keep_busy.record(rec);
        })?;
        recorded?;
        timed.finish(gpu)?;
        let times = timer.read(gpu)?;
        let frame_ms = times.scopes.iter().map(|s| s.1).sum();
        keep_busy.frame_done(gpu, frame_ms)?;
        if warm_up.warming() {
            warm_up.add(frame_ms);
        } else {
            frames.push(times.scopes);
            spans.push(times.span_ms);
        }
    }
    Ok(TimedFrames {
        frames,
        spans,
        warm_up,
    })
}

/// [`frame_loop`] of frames that `record` records (opening timer scopes), each the same:
/// per-stage statistics over the timed frames.
pub fn time_frames(
    gpu: &Gpu,
    plan: FramePlan,
    max_scopes: u32,
    record: impl FnMut(&Recorder, &mut Timer),
) -> Result<Vec<StageStats>> {
    struct Recording<R>(R);
    impl<R: FnMut(&Recorder, &mut Timer)> TimedFrame for Recording<R> {
        type Error = GpuError;
        fn record(&mut self, rec: &Recorder, timer: &mut Timer) -> Result<()> {
            (self.0)(rec, timer);
            Ok(())
        }
    }
    Ok(frame_loop(gpu, plan, max_scopes, &mut Recording(record))?.scope_stats())
}

/// Submits one frame that `record` records, timed as a whole; returns its GPU milliseconds.
/// For single renders (tests, `tessera render`); benchmarks use [`time_frames`].
pub fn time_once<E: From<GpuError>>(
    gpu: &Gpu,
    pass: &str,
    record: impl FnOnce(&Recorder) -> std::result::Result<(), E>,
) -> std::result::Result<f64, E> {
    let mut timer = Timer::new(gpu, 1).map_err(E::from)?;
    timer.reset(gpu);
    let mut recorded = Ok(());
    let submitted = gpu.submit(pass, |rec| {
        recorded = timer.scope(rec, pass, record);
    });
    submitted.map_err(E::from).and(recorded).and_then(|_| {
        Ok(timer
            .read_ms(gpu)
            .map_err(E::from)?
            .first()
            .map(|s| s.1)
            .unwrap_or(0.0))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_median_min_max() {
        let s = StageStats::from_samples("x", &[3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.median_ms, s.min_ms, s.max_ms), (2.5, 1.0, 10.0));
        let s = StageStats::from_samples("x", &[5.0, 1.0, 2.0]);
        assert_eq!(s.median_ms, 2.0);
    }

    #[test]
    fn scope_summed_and_span_stats_of_timed_frames() {
        let scope = |name: &str, ms: f64| (name.to_string(), ms);
        let timed = TimedFrames {
            frames: vec![
                vec![scope("a", 1.0), scope("b", 4.0)],
                vec![scope("a", 3.0)],
                vec![scope("a", 2.0), scope("b", 6.0)],
            ],
            spans: vec![5.5, 3.0, 8.25],
            warm_up: WarmUp::new(FramePlan::default()),
        };
        let stats = timed.scope_stats();
        let names: Vec<&str> = stats.iter().map(|s| s.stage.as_str()).collect();
        assert_eq!(names, ["a", "b"]);
        assert_eq!((stats[0].median_ms, stats[0].max_ms), (2.0, 3.0));
        // The frame without "b" adds no sample to it.
        assert_eq!((stats[1].median_ms, stats[1].min_ms), (5.0, 4.0));
        let sum = timed.sum_stats("frame");
        assert_eq!(
            (sum.stage.as_str(), sum.median_ms, sum.max_ms),
            ("frame", 5.0, 8.0)
        );
        let span = timed.span_stats("frame-span");
        assert_eq!(
            (span.stage.as_str(), span.median_ms, span.max_ms),
            ("frame-span", 5.5, 8.25)
        );
    }

    fn warm_up_frames(plan: FramePlan, frame_ms: impl Fn(u32) -> f64) -> u32 {
        let mut w = WarmUp::new(plan);
        while w.warming() {
            w.add(frame_ms(w.frames()));
        }
        w.frames()
    }

    #[test]
    fn warm_up_runs_until_frame_times_settle() {
        let plan = FramePlan {
            warmup: 3,
            frames: 10,
            max_warmup: 500,
            min_warmup_ms: 0,
            keep_busy_ms: 0.0,
            frames_per_cycle: 1,
        };
        // Steady from the start: the minimum, or two windows when that is more.
        assert_eq!(warm_up_frames(plan, |_| 1.0), 2 * SETTLE_WINDOW as u32);
        // Slow first frames (clocks ramping): warming lasts until two windows agree.
        let ramp = |k: u32| if k < 40 { 5.0 - 0.1 * k as f64 } else { 1.0 };
        let frames = warm_up_frames(plan, ramp);
        assert!(
            (40..40 + 2 * SETTLE_WINDOW as u32 + 1).contains(&frames),
            "{frames}"
        );
        // A stable median with every third frame twice as slow is not settled: warming lasts
        // until the slow frames stop.
        let bimodal = |k: u32| {
            if k < 60 && k.is_multiple_of(3) {
                2.0
            } else {
                1.0
            }
        };
        let frames = warm_up_frames(plan, bimodal);
        assert!(
            (60..60 + SETTLE_WINDOW as u32 + 1).contains(&frames),
            "{frames}"
        );
        // Frame times that keep growing never settle: capped.
        assert_eq!(warm_up_frames(plan, |k| f64::from(k * k)), 500);
        // A fixed warm-up when the cap is not above the minimum.
        let fixed = FramePlan {
            max_warmup: 0,
            ..plan
        };
        assert_eq!(warm_up_frames(fixed, |k| k as f64), 3);
        // Settled frames keep warming up until the wall-time minimum has passed since the first.
        let timed = FramePlan {
            min_warmup_ms: 30,
            max_warmup: u32::MAX,
            ..plan
        };
        let start = Instant::now();
        let frames = warm_up_frames(timed, |_| {
            std::thread::sleep(Duration::from_millis(1));
            1.0
        });
        assert!(start.elapsed() >= Duration::from_millis(30), "{frames}");
        assert!(frames > 2 * SETTLE_WINDOW as u32, "{frames}");
        // The frame cap comes first.
        let capped = FramePlan {
            max_warmup: 20,
            min_warmup_ms: 60_000,
            ..plan
        };
        assert_eq!(warm_up_frames(capped, |_| 1.0), 20);
    }

    #[test]
    fn frames_that_cycle_through_content_settle_by_whole_cycles() {
        let plan = FramePlan {
            warmup: 3,
            frames: 10,
            max_warmup: 200,
            min_warmup_ms: 0,
            keep_busy_ms: 0.0,
            frames_per_cycle: 1,
        };
        // Four steps of 1, 2, 1 and 3 ms: frame by frame the spread rule never holds.
        let steps = |k: u32| [1.0, 2.0, 1.0, 3.0][k as usize % 4];
        let by_frame = warmed_up(plan, steps);
        assert_eq!((by_frame.frames(), by_frame.settled()), (200, false));
        // By cycles of four, every cycle takes 7 ms: settled after two windows of cycles.
        let cycles = FramePlan {
            frames_per_cycle: 4,
            ..plan
        };
        let by_cycle = warmed_up(cycles, steps);
        assert_eq!(
            (by_cycle.frames(), by_cycle.settled()),
            (4 * 2 * SETTLE_WINDOW as u32, true)
        );
        // Only whole cycles count: a cycle whose slow step grows keeps it warming up until the
        // growth stops (here after frame 100), then two windows of cycles follow.
        let ramp = |k: u32| {
            if k % 4 == 3 && k < 100 {
                3.0 + 0.1 * f64::from(k)
            } else {
                steps(k)
            }
        };
        let frames = warmed_up(cycles, ramp).frames();
        assert!(frames.is_multiple_of(4), "{frames}");
        assert!(
            (100..=100 + 4 * 2 * SETTLE_WINDOW as u32 + 4).contains(&frames),
            "{frames}"
        );
    }

    fn warmed_up(plan: FramePlan, frame_ms: impl Fn(u32) -> f64) -> WarmUp {
        let mut w = WarmUp::new(plan);
        while w.warming() {
            w.add(frame_ms(w.frames()));
        }
        w
    }

    #[test]
    fn a_warm_up_says_whether_it_ended_settled() {
        let plan = FramePlan {
            warmup: 3,
            frames: 10,
            max_warmup: 100,
            min_warmup_ms: 0,
            keep_busy_ms: 0.0,
            frames_per_cycle: 1,
        };
        assert!(warmed_up(plan, |_| 1.0).settled());
        // Capped while still moving: growing frames, or every third frame twice as slow.
        let growing = warmed_up(plan, |k| f64::from(k * k));
        assert_eq!((growing.frames(), growing.settled()), (100, false));
        let bimodal = warmed_up(plan, |k| if k.is_multiple_of(3) { 2.0 } else { 1.0 });
        assert_eq!((bimodal.frames(), bimodal.settled()), (100, false));
        // A fixed warm-up shorter than two windows cannot say its frames settled.
        let fixed = FramePlan {
            max_warmup: 0,
            ..plan
        };
        assert!(!warmed_up(fixed, |_| 1.0).settled());
        // The wall-time minimum not yet passed when the cap came: not settled either.
        let capped = FramePlan {
            max_warmup: 20,
            min_warmup_ms: 60_000,
            ..plan
        };
        assert!(!warmed_up(capped, |_| 1.0).settled());
        // Statistics carry it.
        let stats = StageStats::from_samples("x", &[1.0]).after_warmup(&warmed_up(plan, |_| 1.0));
        assert_eq!(
            (stats.warmup_frames, stats.settled),
            (2 * SETTLE_WINDOW as u32, true)
        );
        assert!(!StageStats::from_samples("x", &[1.0]).settled);
    }
}
