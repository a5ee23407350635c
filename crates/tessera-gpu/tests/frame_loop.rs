//! The benchmark frame loop: every frame, warm-up included, is recorded and then finished once
//! its submission completed; only the frames after the warm-up are kept, each
//! with its scopes; an error from recording or finishing ends the loop and comes back.

mod common;
use common::{assert_clean, fill_target, open};
use tessera_gpu::timing::{frame_loop, FramePlan, TimedFrame};
use tessera_gpu::{Buffer, GpuError, Recorder, Timer};

/// Fills a buffer in one scope per frame and logs what the loop asked of it.
struct Fills<'a> {
    work: &'a Buffer,
    /// "r<frames finished before>" for each recording, "f" for each finish.
    log: Vec<String>,
    finished: u32,
    /// The frame whose finish fails.
    fail_at: Option<u32>,
}

impl<'a> Fills<'a> {
    fn new(work: &'a Buffer, fail_at: Option<u32>) -> Fills<'a> {
        Fills {
            work,
            log: Vec::new(),
            finished: 0,
            fail_at,
        }
    }
}

impl TimedFrame for Fills<'_> {
    type Error = GpuError;

    fn record(&mut self, rec: &Recorder, timer: &mut Timer) -> Result<(), GpuError> {
        let frame = self.finished;
        self.log.push(format!("r{frame}"));
        timer.scope(rec, "fill", |rec| rec.fill_buffer(self.work, frame));
        Ok(())
    }

    fn finish(&mut self, _gpu: &tessera_gpu::Gpu) -> Result<(), GpuError> {
        self.log.push("f".into());
        let frame = self.finished;
        self.finished += 1;
        if self.fail_at == Some(frame) {
            return Err(GpuError::Invalid(format!("frame {frame} failed")));
        }
        Ok(())
    }
}

fn plan() -> FramePlan {
    // At or below `warmup`, `max_warmup` makes the warm-up exactly `warmup` frames.
    FramePlan {
        warmup: 3,
        frames: 4,
        max_warmup: 0,
        min_warmup_ms: 0,
        keep_busy_ms: 2.0,
        frames_per_cycle: 1,
    }
}

#[test]
fn every_frame_is_recorded_then_finished_and_only_the_timed_ones_are_kept() {
    let Some(gpu) = open() else { return };
    let work = fill_target(&gpu);
    let mut fills = Fills::new(&work, None);
    let timed = frame_loop(&gpu, plan(), 1, &mut fills).unwrap();
    let expected: Vec<String> = (0..7).flat_map(|k| [format!("r{k}"), "f".into()]).collect();
    assert_eq!(fills.log, expected);
    assert_eq!(timed.warm_up.frames(), 3);
    assert_eq!(timed.frames.len(), 4);
    assert!(timed
        .frames
        .iter()
        .all(|f| f.len() == 1 && f[0].0 == "fill" && f[0].1.is_finite() && f[0].1 >= 0.0));
    let stats = timed.scope_stats();
    assert_eq!(stats.len(), 1);
    assert_eq!(
        (stats[0].stage.as_str(), stats[0].warmup_frames),
        ("fill", 3)
    );
    assert_eq!(timed.sum_stats("frame").median_ms, stats[0].median_ms);
    // One scope spans its frame.
    assert_eq!(timed.spans.len(), 4);
    for (span, scopes) in timed.spans.iter().zip(&timed.frames) {
        assert_eq!(*span, scopes[0].1);
    }
    assert_clean(&gpu);
}

/// Two timed fills with untimed fills between them.
struct Gapped<'a> {
    work: &'a Buffer,
}

impl TimedFrame for Gapped<'_> {
    type Error = GpuError;

    fn record(&mut self, rec: &Recorder, timer: &mut Timer) -> Result<(), GpuError> {
        timer.scope(rec, "first", |rec| rec.fill_buffer(self.work, 1));
        for value in 0..64 {
            rec.barrier();
            rec.fill_buffer(self.work, value);
        }
        rec.barrier();
        timer.scope(rec, "second", |rec| rec.fill_buffer(self.work, 2));
        Ok(())
    }
}

#[test]
fn a_frames_span_holds_its_scopes_and_the_work_between_them() {
    let Some(gpu) = open() else { return };
    let work = fill_target(&gpu);
    let timed = frame_loop(&gpu, plan(), 2, &mut Gapped { work: &work }).unwrap();
    assert_eq!(timed.spans.len(), timed.frames.len());
    for (span, scopes) in timed.spans.iter().zip(&timed.frames) {
        let names: Vec<&str> = scopes.iter().map(|s| s.0.as_str()).collect();
        assert_eq!(names, ["first", "second"]);
        let sum: f64 = scopes.iter().map(|s| s.1).sum();
        // The timestamps wait for all earlier commands: scopes follow each other in time.
        assert!(
            *span >= sum && span.is_finite(),
            "span {span} ms, scopes {scopes:?}"
        );
    }
    assert!(timed.span_stats("frame-span").median_ms >= timed.sum_stats("frame").median_ms);
    assert_clean(&gpu);
}

#[test]
fn a_failing_finish_ends_the_loop_with_its_error() {
    let Some(gpu) = open() else { return };
    let work = fill_target(&gpu);
    let mut fills = Fills::new(&work, Some(4));
    let Err(error) = frame_loop(&gpu, plan(), 1, &mut fills) else {
        panic!("the loop went on past a failed frame");
    };
    assert!(error.to_string().contains("frame 4 failed"), "{error}");
    assert_eq!(fills.log.len(), 10, "{:?}", fills.log);
    assert_clean(&gpu);
}
