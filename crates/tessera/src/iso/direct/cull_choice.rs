//! Whether occlusion culling pays on the compute path, decided frame by frame from the counts
//! the frames report (no timing on the GPU).
//!
//! A culled frame costs a fixed extra (the depth pyramid, the occlusion test, a second
//! extraction pass) plus each drawn block at a higher rate than an unculled frame pays per
//! occupied block (a block is extracted in one of two passes and its triangles rasterized into
//! a depth buffer that is read back). So culling pays only where it draws a small enough share
//! of the occupied blocks. The rates are the H200's (docs/BENCHMARKS.md, "Skipping culling
//! where it does not pay"): head 256³ and 512³, 1280×720 to 3840×2160, runs 58–59.

/// Per-block and per-frame costs of the two ways to draw a frame, in nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CullingCosts {
    /// A culled frame, per block drawn in either pass.
    pub culled_per_drawn_block: f64,
    /// An unculled frame, per occupied block.
    pub unculled_per_occupied_block: f64,
    /// What a culled frame costs more with nothing to draw, per pixel.
    pub culled_extra_per_pixel: f64,
}

impl CullingCosts {
    /// Measured on the H200: 57 ns a drawn block culled, 35 ns an occupied block unculled,
    /// and 0.040 ms more for an empty culled frame at 3840×2160.
    pub const H200: CullingCosts = CullingCosts {
        culled_per_drawn_block: 57.0,
        unculled_per_occupied_block: 35.0,
        culled_extra_per_pixel: 40_000.0 / (3840.0 * 2160.0),
    };

    /// Whether a frame that draws `drawn` of `occupied` blocks at `pixels` pixels costs less
    /// culled than unculled.
    pub fn culling_pays(&self, drawn: u32, occupied: u32, pixels: u64) -> bool {
        let culled = self.culled_extra_per_pixel * pixels as f64
            + self.culled_per_drawn_block * drawn as f64;
        let unculled = self.unculled_per_occupied_block * occupied as f64;
        culled < unculled
    }
}

/// Unculled frames between two probes of culling.
pub const PROBE_INTERVAL: u32 = 30;
/// Culled frames a probe lasts: the first draws the visible set of a frame long past, so the
/// choice is made on the second.
pub const PROBE_FRAMES: u32 = 2;

/// The automatic choice: cull while culling pays; once it does not, draw unculled and probe
/// culling again every [`PROBE_INTERVAL`] frames (the view or the data may have changed).
#[derive(Debug, Clone, PartialEq)]
pub struct AutoCulling {
    costs: CullingCosts,
    state: Choice,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Choice {
    /// Culling; `probe_left` culled frames until a decision may be taken.
    Culled { probe_left: u32 },
    /// Unculled for `frames` frames so far.
    Unculled { frames: u32 },
}

impl AutoCulling {
    pub fn new(costs: CullingCosts) -> AutoCulling {
        AutoCulling {
            costs,
            state: Choice::Culled {
                probe_left: PROBE_FRAMES - 1,
            },
        }
    }

    /// Whether the next frame is to be culled.
    pub fn cull_next(&self) -> bool {
        matches!(self.state, Choice::Culled { .. })
    }

    /// Starts over with a probe (new data, look or image size: what was measured no longer
    /// holds).
    pub fn reset(&mut self) {
        *self = AutoCulling::new(self.costs);
    }

    /// After a culled frame that drew `drawn` of `occupied` blocks.
    pub fn after_culled(&mut self, drawn: u32, occupied: u32, pixels: u64) {
        self.state = match self.state {
            Choice::Culled { probe_left } if probe_left > 0 => Choice::Culled {
                probe_left: probe_left - 1,
            },
            _ if self.costs.culling_pays(drawn, occupied, pixels) => {
                Choice::Culled { probe_left: 0 }
            }
            _ => Choice::Unculled { frames: 0 },
        };
    }

    /// After an unculled frame.
    pub fn after_unculled(&mut self) {
        self.state = match self.state {
            Choice::Unculled { frames } if frames + 1 < PROBE_INTERVAL => {
                Choice::Unculled { frames: frames + 1 }
            }
            _ => Choice::Culled {
                probe_left: PROBE_FRAMES - 1,
            },
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PIXELS_4K: u64 = 3840 * 2160;

    #[test]
    fn measured_frames_choose_the_faster_way() {
        let costs = CullingCosts::H200;
        // Head 256³ at 30 % of the range, 4K (run 59): 3,488 of 10,486 blocks drawn, culled
        // 0.348 ms against unculled 0.477 ms.
        assert!(costs.culling_pays(3488, 10486, PIXELS_4K));
        // Nothing to draw: culled 0.148 ms against unculled 0.108 ms.
        assert!(!costs.culling_pays(0, 0, PIXELS_4K));
        // Every occupied block drawn: culling only adds its passes.
        assert!(!costs.culling_pays(10486, 10486, PIXELS_4K));
        // The break-even share lies between a half and two thirds of the occupied blocks.
        assert!(costs.culling_pays(5000, 10000, PIXELS_4K));
        assert!(!costs.culling_pays(6500, 10000, PIXELS_4K));
    }

    #[test]
    fn stays_culled_while_culling_pays() {
        let mut auto = AutoCulling::new(CullingCosts::H200);
        for _ in 0..100 {
            assert!(auto.cull_next());
            auto.after_culled(3000, 10000, PIXELS_4K);
        }
    }

    #[test]
    fn decides_after_the_probe_and_probes_again() {
        let mut auto = AutoCulling::new(CullingCosts::H200);
        // The first culled frame of a probe decides nothing, however it came out.
        assert!(auto.cull_next());
        auto.after_culled(10000, 10000, PIXELS_4K);
        assert!(auto.cull_next());
        auto.after_culled(10000, 10000, PIXELS_4K);
        for _ in 0..PROBE_INTERVAL {
            assert!(!auto.cull_next());
            auto.after_unculled();
        }
        // The probe: two culled frames; this time culling pays, so it stays.
        assert!(auto.cull_next());
        auto.after_culled(10000, 10000, PIXELS_4K);
        assert!(auto.cull_next());
        auto.after_culled(1000, 10000, PIXELS_4K);
        assert!(auto.cull_next());
        auto.after_culled(1000, 10000, PIXELS_4K);
        assert!(auto.cull_next());
    }

    #[test]
    fn reset_probes_at_once() {
        let mut auto = AutoCulling::new(CullingCosts::H200);
        auto.after_culled(0, 0, PIXELS_4K);
        auto.after_culled(0, 0, PIXELS_4K);
        assert!(!auto.cull_next());
        auto.reset();
        assert!(auto.cull_next());
    }
}
