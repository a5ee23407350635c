//! Which compute scheme draws the next frame when the choice is automatic: the one whose last
//! frame took the least GPU time, the other measured afresh every [`PROBE_INTERVAL`] frames, or
//! up to [`MAX_PROBE_BACKOFF`] times less often while it keeps losing (a probe of the slower
//! scheme is a slow frame: 2× the time inside the 2.4 M-tet box), and at once when the faster
//! one's frames have moved by more than [`STALE_RATIO`] since the two were compared (the view
//! changed: the 64 k-tet box seen far takes 3.2 ms per tet against 3.5 binned, close 13.5
//! against 8.4, and the close view kept the per-tet pass until the next probe was due, 60
//! frames on, or up to 960 after lost probes; docs/BENCHMARKS.md, run 102).
//!
//! Neither scheme wins everywhere (docs/BENCHMARKS.md, run 62): binning is up to 2.5× faster
//! on most meshes and views, but 13–28 % slower where a huge mesh is seen small, and no count
//! known before drawing told the two apart (the far view of the 944 k-tet box and the inside
//! view of the 2.4 M-tet box have the same tets per covered pixel, and opposite winners). So
//! the renderer times its own frames and lets the times decide.

/// The two ways the compute path draws a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawScheme {
    PerTet,
    Binned,
}

impl DrawScheme {
    fn other(self) -> DrawScheme {
        match self {
            DrawScheme::PerTet => DrawScheme::Binned,
            DrawScheme::Binned => DrawScheme::PerTet,
        }
    }

    fn index(self) -> usize {
        match self {
            DrawScheme::PerTet => 0,
            DrawScheme::Binned => 1,
        }
    }
}

/// Frames drawn with the faster scheme between two frames of the other.
pub const PROBE_INTERVAL: u32 = 60;
/// The most the probe interval grows (doubling with each probe the other scheme loses).
pub const MAX_PROBE_BACKOFF: u32 = 16;
/// How many times slower or faster the preferred scheme's frames may get than they were when
/// the two schemes were last compared before the comparison is taken as stale and the other
/// scheme is measured again. Frame times of one view move by a few percent (noise, clocks).
pub const STALE_RATIO: f64 = 1.25;

/// The automatic choice and the GPU times it rests on.
#[derive(Debug, Clone, PartialEq)]
pub struct AutoScheme {
    /// The last measured frame time of each scheme (milliseconds), by [`DrawScheme::index`].
    last_ms: [Option<f64>; 2],
    /// The scheme of the frames between probes.
    preferred: DrawScheme,
    /// Frames since the other scheme was last measured.
    since_probe: u32,
    /// The current probe interval in units of [`PROBE_INTERVAL`].
    backoff: u32,
    /// The preferred scheme's frame time when the two were last compared.
    compared_at_ms: Option<f64>,
}

impl Default for AutoScheme {
    fn default() -> Self {
        AutoScheme {
            last_ms: [None; 2],
            preferred: DrawScheme::Binned,
            since_probe: 0,
            backoff: 1,
            compared_at_ms: None,
        }
    }
}

impl AutoScheme {
    /// Whether the preferred scheme's last frame moved by more than [`STALE_RATIO`] from its
    /// time when the two schemes were compared.
    fn stale(&self) -> bool {
        match (self.compared_at_ms, self.last_ms[self.preferred.index()]) {
            (Some(then), Some(now)) => now > then * STALE_RATIO || now * STALE_RATIO < then,
            _ => false,
        }
    }

    /// The scheme of the next frame: the other one when it has not been measured yet or is due
    /// a new measurement, else the faster.
    pub fn next(&self) -> DrawScheme {
        let other = self.preferred.other();
        let due = self.since_probe >= PROBE_INTERVAL * self.backoff || self.stale();
        if self.last_ms[self.preferred.index()].is_some()
            && (self.last_ms[other.index()].is_none() || due)
        {
            other
        } else {
            self.preferred
        }
    }

    /// After a frame drawn with `scheme` that took `ms` of GPU time. A frame whose bin lists
    /// `overflowed` drew the tets they had no room for per tet, slowly: it measures neither
    /// scheme (the lists grow, and the next frame measures again). The first binned frame on
    /// a large mesh does this (the 2.4 M-tet box needs 8–14 M entries, the lists start with
    /// 4 M): counted, it made per tet look faster where binning takes half its time.
    pub fn after_frame(&mut self, scheme: DrawScheme, ms: f64, overflowed: bool) {
        if overflowed {
            return;
        }
        let first_measure = self.last_ms[scheme.index()].is_none();
        self.last_ms[scheme.index()] = Some(ms);
        if scheme == self.preferred {
            self.since_probe += 1;
            return;
        }
        self.since_probe = 0;
        // A probe the preferred scheme's change asked for says nothing about how often the
        // other needs measuring where nothing changes.
        let stale = self.stale();
        let preferred_ms = self.last_ms[self.preferred.index()];
        if preferred_ms.is_some_and(|p| ms < p) {
            self.preferred = scheme;
            self.backoff = 1;
        } else if !first_measure && !stale {
            self.backoff = (self.backoff * 2).min(MAX_PROBE_BACKOFF);
        }
        self.compared_at_ms = self.last_ms[self.preferred.index()];
    }

    /// Forgets the times (new data or another image size: they no longer hold).
    pub fn reset(&mut self) {
        *self = AutoScheme::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `frames` frames whose time each scheme's function gives (by frame number).
    fn run(
        auto: &mut AutoScheme,
        frames: u32,
        per_tet: impl Fn(u32) -> f64,
        binned: impl Fn(u32) -> f64,
    ) -> Vec<DrawScheme> {
        (0..frames)
            .map(|k| {
                let scheme = auto.next();
                let ms = match scheme {
                    DrawScheme::PerTet => per_tet(k),
                    DrawScheme::Binned => binned(k),
                };
                auto.after_frame(scheme, ms, false);
                scheme
            })
            .collect()
    }

    /// The frames drawn with `scheme`.
    fn frames_with(schemes: &[DrawScheme], scheme: DrawScheme) -> Vec<usize> {
        (0..schemes.len())
            .filter(|&k| schemes[k] == scheme)
            .collect()
    }

    #[test]
    fn measures_both_then_keeps_the_faster() {
        let mut auto = AutoScheme::default();
        let schemes = run(&mut auto, 10, |_| 26.0, |_| 36.0);
        assert_eq!(schemes[0], DrawScheme::Binned, "binning first");
        assert_eq!(schemes[1], DrawScheme::PerTet, "then the other");
        assert!(schemes[2..].iter().all(|&s| s == DrawScheme::PerTet));
        let mut auto = AutoScheme::default();
        let schemes = run(&mut auto, 10, |_| 6.1, |_| 2.8);
        assert!(schemes[2..].iter().all(|&s| s == DrawScheme::Binned));
    }

    #[test]
    fn probes_less_often_while_the_other_loses_and_follows_a_change() {
        let mut auto = AutoScheme::default();
        // Binning is faster until frame 300, then per tet is (the view moved away).
        let schemes = run(
            &mut auto,
            500,
            |_| 10.0,
            |k| if k < 300 { 5.0 } else { 15.0 },
        );
        let at = |from: usize, to: usize, scheme| schemes[from..to].iter().all(|&s| s == scheme);
        let interval = PROBE_INTERVAL as usize;
        // Frame 1 measures per tet; the probes after it come after 60 and 120 binned frames.
        let probes = [1, 2 + interval, 3 + 3 * interval];
        let per_tet = frames_with(&schemes[..300], DrawScheme::PerTet);
        assert_eq!(per_tet, probes);
        // Frame 300's binned frame took three times its time at the last comparison: frame 301
        // measures per tet, finds it faster and keeps it; binning's probes, 60 and then 120
        // frames later, lose.
        assert_eq!(schemes[300], DrawScheme::Binned);
        assert!(at(301, 302 + interval, DrawScheme::PerTet));
        assert_eq!(schemes[302 + interval], DrawScheme::Binned);
        assert!(at(303 + interval, 303 + 3 * interval, DrawScheme::PerTet));
        assert_eq!(schemes[303 + 3 * interval], DrawScheme::Binned);
        assert!(at(304 + 3 * interval, 500, DrawScheme::PerTet));
    }

    #[test]
    fn a_view_that_slows_the_faster_scheme_measures_the_other_at_once() {
        // The 64 k-tet box far (per tet 3.2 ms, binned 3.5), then close from frame 100 (per
        // tet 13.5, binned 8.4): run 102.
        let mut auto = AutoScheme::default();
        let schemes = run(
            &mut auto,
            200,
            |k| if k < 100 { 3.2 } else { 13.5 },
            |k| if k < 100 { 3.5 } else { 8.4 },
        );
        assert!(schemes[2..62].iter().all(|&s| s == DrawScheme::PerTet));
        assert_eq!(schemes[100], DrawScheme::PerTet);
        // Binning from the frame after the slow per-tet frame, until per tet's next probe.
        let interval = PROBE_INTERVAL as usize;
        assert!(schemes[101..102 + interval]
            .iter()
            .all(|&s| s == DrawScheme::Binned));
        assert_eq!(schemes[102 + interval], DrawScheme::PerTet);
        // A faster view probes too: back far from frame 200 (binned 3.5, per tet 3.2).
        let schemes = run(&mut auto, 10, |_| 3.2, |_| 3.5);
        assert_eq!(
            schemes[..3],
            [DrawScheme::Binned, DrawScheme::PerTet, DrawScheme::PerTet]
        );
    }

    #[test]
    fn a_probe_the_change_asked_for_keeps_the_interval() {
        // Per tet faster throughout, its frames 40 % slower from frame 100: binning is
        // measured at frame 101, loses, and is next measured 120 frames later, as before.
        let mut auto = AutoScheme::default();
        let schemes = run(
            &mut auto,
            400,
            |k| if k < 100 { 10.0 } else { 14.0 },
            |_| 20.0,
        );
        let binned = frames_with(&schemes, DrawScheme::Binned);
        assert_eq!(binned, [0, 62, 101, 222]);
    }

    #[test]
    fn frame_times_that_move_a_little_do_not_probe() {
        // Per tet 10 % apart from frame to frame, binning twice as fast.
        let mut auto = AutoScheme::default();
        let schemes = run(
            &mut auto,
            2000,
            |k| if k % 2 == 0 { 10.0 } else { 11.0 },
            |k| if k % 3 == 0 { 5.0 } else { 5.5 },
        );
        let probes = frames_with(&schemes, DrawScheme::PerTet);
        let gaps: Vec<usize> = probes.windows(2).map(|w| w[1] - w[0] - 1).collect();
        assert_eq!(gaps, [60, 120, 240, 480, 960]);
    }

    #[test]
    fn the_probe_interval_stops_growing() {
        let mut auto = AutoScheme::default();
        let schemes = run(&mut auto, 10_000, |_| 10.0, |_| 5.0);
        let probes = frames_with(&schemes, DrawScheme::PerTet);
        let gaps: Vec<usize> = probes.windows(2).map(|w| w[1] - w[0] - 1).collect();
        let longest = (PROBE_INTERVAL * MAX_PROBE_BACKOFF) as usize;
        assert_eq!(gaps[..5], [60, 120, 240, 480, 960]);
        assert!(gaps[5..].iter().all(|&g| g == longest), "{gaps:?}");
    }

    #[test]
    fn a_frame_whose_lists_overflowed_measures_nothing() {
        // The box seen from inside (run 63): binned 85.6 ms, per tet 177 ms; the first binned
        // frame, its lists too short, also drew the overflow per tet.
        let mut auto = AutoScheme::default();
        assert_eq!(auto.next(), DrawScheme::Binned);
        auto.after_frame(DrawScheme::Binned, 230.0, true);
        assert_eq!(
            auto.next(),
            DrawScheme::Binned,
            "measured again, lists grown"
        );
        auto.after_frame(DrawScheme::Binned, 85.6, false);
        assert_eq!(auto.next(), DrawScheme::PerTet);
        auto.after_frame(DrawScheme::PerTet, 177.0, false);
        assert_eq!(auto.next(), DrawScheme::Binned);
        // A probe of binning that overflows (the view took in more tets) is taken again.
        let mut auto = AutoScheme::default();
        auto.after_frame(DrawScheme::Binned, 36.0, false);
        auto.after_frame(DrawScheme::PerTet, 26.0, false);
        for _ in 0..PROBE_INTERVAL {
            assert_eq!(auto.next(), DrawScheme::PerTet);
            auto.after_frame(DrawScheme::PerTet, 26.0, false);
        }
        assert_eq!(auto.next(), DrawScheme::Binned);
        auto.after_frame(DrawScheme::Binned, 60.0, true);
        assert_eq!(auto.next(), DrawScheme::Binned);
        auto.after_frame(DrawScheme::Binned, 20.0, false);
        assert_eq!(auto.next(), DrawScheme::Binned, "binning now faster");
    }

    #[test]
    fn reset_measures_again() {
        let mut auto = AutoScheme::default();
        run(&mut auto, 5, |_| 1.0, |_| 2.0);
        assert_eq!(auto.next(), DrawScheme::PerTet);
        auto.reset();
        assert_eq!(auto.next(), DrawScheme::Binned);
    }
}
