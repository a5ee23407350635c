//! Options of `param-tess` and the checks that refuse what the device or the level rule cannot
//! do.

use crate::error::{Error, Result};
use crate::param::ParamPointsOptions;
use tessera_gpu::pipeline::sample_count_flag;
use tessera_gpu::Gpu;

/// Paper E's clamp of adaptive levels.
pub const DEFAULT_MIN_LEVEL: u32 = 8;
pub const DEFAULT_MAX_LEVEL: u32 = 64;

/// How patches are subdivided (module documentation has the rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TessLevels {
    /// Every inner and outer level is this.
    Fixed(u32),
    /// Levels from screen lengths, one segment per `pixels_per_segment` pixels.
    Adaptive { pixels_per_segment: f32 },
}

/// Settings of `param-tess`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamTessOptions {
    /// `(t_u, t_v)` in raster pixels (paper: 84 for SH glyphs).
    pub thresholds: [f32; 2],
    /// LOD steps (paper: 12).
    pub max_steps: u32,
    pub frustum_culling: bool,
    /// Patches each patch list holds (32 bytes each, three lists).
    pub patch_capacity: u32,
    /// As [`crate::param::ParamPointsOptions::pre_split`].
    pub pre_split: u32,
    pub levels: TessLevels,
    /// Clamp of adaptive levels, `1 <= min_level <= max_level <= ` the device's limit.
    pub min_level: u32,
    pub max_level: u32,
    /// Samples per pixel: 1 (off), 2, 4 or 8 where the device has them.
    pub msaa: u32,
    /// Render at `k × k` raster pixels per image pixel and average them.
    pub supersample: u32,
    /// For tests: colour each fragment with its patch's inner levels, `(r, g) = level / 255`,
    /// instead of shading it.
    pub debug_levels: bool,
}

impl Default for ParamTessOptions {
    fn default() -> Self {
        let lod = ParamPointsOptions::default();
        ParamTessOptions {
            thresholds: lod.thresholds,
            max_steps: lod.max_steps,
            frustum_culling: lod.frustum_culling,
            patch_capacity: lod.patch_capacity,
            pre_split: lod.pre_split,
            levels: TessLevels::Adaptive {
                pixels_per_segment: 1.0,
            },
            min_level: DEFAULT_MIN_LEVEL,
            max_level: DEFAULT_MAX_LEVEL,
            msaa: 1,
            supersample: 1,
            debug_levels: false,
        }
    }
}

/// Mesa's CPU rasterizer (lavapipe) indexes the vertices the evaluation stage makes for one
/// run of its pipeline with 16 bits (`draw_tess.c`), and a run covers one instance of a draw:
/// past 65,536 vertices the triangles join wrong vertices. On CPU devices an instance holds at
/// most as many patches as stay below that at the highest level (15 at level 64; each patch's
/// vertices are rounded up to a multiple of 4 there); elsewhere one instance holds them all.
pub(super) fn patches_per_instance(gpu: &Gpu, options: &ParamTessOptions) -> u32 {
    if !gpu.caps().is_cpu() {
        return options.patch_capacity;
    }
    let top = match options.levels {
        TessLevels::Fixed(l) => l,
        TessLevels::Adaptive { .. } => options.max_level,
    };
    let vertices = ((top + 1) * (top + 1)).next_multiple_of(4);
    (65_536 / vertices).max(1)
}

/// Refuses options the device or the rule cannot honour, naming the limit.
pub(super) fn check_options(gpu: &Gpu, o: &ParamTessOptions) -> Result<()> {
    let caps = gpu.caps();
    let fail = |what: String| Err(Error::Invalid(format!("param-tess: {what}")));
    if !caps.tessellation {
        return fail(format!("{} has no tessellation shaders", caps.device_name));
    }
    let device_max = caps.max_tessellation_level;
    match o.levels {
        TessLevels::Fixed(l) if !(1..=device_max).contains(&l) => {
            return fail(format!("fixed level {l} is outside 1..={device_max}"));
        }
        TessLevels::Adaptive {
            pixels_per_segment: p,
        } if !(p.is_finite() && p > 0.0) => {
            return fail(format!("pixels per segment must be positive, got {p}"));
        }
        _ => {}
    }
    if !(1 <= o.min_level && o.min_level <= o.max_level && o.max_level <= device_max) {
        return fail(format!(
            "adaptive levels need 1 <= min <= max <= {device_max} (the device's limit), got \
             {} and {}",
            o.min_level, o.max_level
        ));
    }
    let supported = gpu.attachment_sample_counts();
    let usable = [1, 2, 4, 8].contains(&o.msaa)
        && sample_count_flag(o.msaa).is_some_and(|f| supported.contains(f));
    if !usable {
        return fail(format!(
            "{} has no {}-sample colour and depth attachments (it has {supported:?})",
            caps.device_name, o.msaa
        ));
    }
    if !(1..=8).contains(&o.supersample) {
        return fail(format!(
            "supersampling must be 1 to 8, got {}",
            o.supersample
        ));
    }
    Ok(())
}
