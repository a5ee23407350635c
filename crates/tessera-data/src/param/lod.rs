//! CPU reference of paper E's PATCH SUBDIVISION stage (§4.1, Figs. 5 and 6): the rules a GPU
//! compute shader must reproduce, written so that it can do so exactly.
//!
//! Input: patches `[u0, u1] × [v0, v1]` with an object id (PATCH INITIALIZATION's output), a
//! surface `f(object, u, v)` and a projection to pixels (`None` = behind the camera).
//!
//! **Samples** (Fig. 6; all arithmetic in `f32`, each operation rounded separately, no fused
//! multiply-add — GLSL needs `precise`). With `du = u1 - u0`, `dv = v1 - v0`,
//! `step = d / 7.0`, `quarter = d * 0.25`:
//! * u-line `k` (k = 0..4), sample `i` (i = 0..8): `(u0 + step_u * i, v0 + quarter_v * (k + 0.5))`;
//! * v-line `k`, sample `j`: `(u0 + quarter_u * (k + 0.5), v0 + step_v * j)`;
//! * culling grid `(a, b)`, `a, b = 0..5`, index `5b + a`:
//!   `(clamp(u0 + quarter_u * a, u0, u1), clamp(v0 + quarter_v * b, v0, v1))`.
//!
//! A projected position with a NaN coordinate counts as behind the camera.
//!
//! Given the same projected positions, a shader following these rules reproduces every flag,
//! pattern and child range bit for bit; only `sqrt` may differ by the few ulps Vulkan allows.
//! The positions themselves will not match exactly, since GPU `sin`/`cos`/`exp` are
//! approximations: GPU tests should feed both sides the same positions, or avoid ties with `t`.
//!
//! **Extents.** Each line's extent `e` is the sum of its 7 segment lengths, added in order
//! `((s1 + s2) + s3) + …` starting from `0.0`. A segment is `sqrt(dx*dx + dy*dy)` between its
//! endpoints clamped to the viewport `[0, W] × [0, H]` (`min(max(x, 0), W)`), so geometry off
//! screen asks for no detail — as in the authors' shader, which clamps clip coordinates to the
//! frustum. A segment with an endpoint behind the camera has length 0: the projection of that
//! stretch is unknown, its visible part is measured by the neighbouring segments, and triangles
//! crossing the eye plane are clipped by the rasteriser anyway.
//!
//! **Split flags.** Line `k` requests a split when `e_k > t` (strictly; paper: "if e > t").
//! `a = su0 || su1` (u-lines in the lower v half), `b = su2 || su3` (upper v half),
//! `c = sv0 || sv1` (v-lines in the lower u half), `d = sv2 || sv3`. A u-line asks for its v
//! half to be split into two u intervals, a v-line for its u half to be split into two v
//! intervals (§4.1). The 16 flag combinations map to the eight outcomes of Fig. 5
//! ([`SplitPattern::decide`]): halve v if `c && d` or `a != b`; otherwise halve u if `a && b`
//! or `c != d`; otherwise keep. Halving v, the lower half is also halved in u
//! iff `a`, the upper iff `b`; halving u, the lower-u half is also halved in v iff `c`, the upper
//! iff `d`. Every requested split is thus made, and a split confined to one half needs the
//! perpendicular halving that isolates that half (3 patches). Midpoints are `u0 + du * 0.5`,
//! and children reuse the parent's exact endpoints, so they tile the parent.
//!
//! **Culling** (optional). Each of the 89 samples (32 + 32 line samples and the 25 grid samples,
//! which the paper adds so that a patch whose corner pokes into view is not culled) gets an
//! outcode: behind = 16, else left (`x < 0`) = 1 | right (`x > W`) = 2 | top (`y < 0`) = 4 |
//! bottom (`y > H`) = 8. The patch is dropped when the AND of all 89 outcodes is non-zero, i.e.
//! every sample lies outside the same side.
//!
//! **Steps.** Up to `n` LOD steps (paper: 12). A kept patch goes to "patches to render" with its
//! extents `(max e_u, max e_v)`. Split children go to the next step, except in step `n`, where
//! they are rendered anyway ("except in LOD step n", §4.1) and flagged `over_threshold`; their
//! extents are the parent's maxima over the lines inside the child, halved along a halved
//! direction. A range too small for `f32` to halve is not split (its flags are dropped, and a
//! split the other way is made whole-range instead); a patch kept with a raised flag is flagged
//! `over_threshold` too. Output order is deterministic (input order, children in
//! [`SplitPattern::children`] order), whereas a GPU's atomics give an arbitrary order: compare
//! sets.
//!
//! **Sources.** The paper's text fixes 8 samples on each of 4 lines per direction, the 25 extra
//! culling samples, `e > t`, the eight outcomes and `n = 12`; Figs. 5 and 6 themselves are not in
//! the text, so sample positions, the flag-to-pattern mapping and the viewport clamping follow
//! the authors' shader (`pass2x_patch_lod.comp`, cg-tuwien/FastRenderingOfParametricObjects).
//! Deliberate differences from that shader: `>` instead of its `>=` (the paper's wording);
//! culling uses all 89 samples (the shader's test repeats its u-line samples where the v-line
//! ones were evidently meant); midpoints keep exact endpoints (the shader recomputes the upper
//! end as `u0 + half + half`, which can leave gaps or overlaps of one ulp).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::functions::ParamDomain;
pub use super::split::SplitPattern;
use super::split::{halvable, part};
use crate::error::{DataError, Result};

pub const DEFAULT_MAX_STEPS: u32 = 12;
/// Paper E's threshold for SH glyphs (`t_u = t_v = 84`, Fig. 8–9).
pub const DEFAULT_THRESHOLD: f32 = 84.0;
/// Largest step count accepted; far beyond what `f32` parameters can resolve.
pub const MAX_STEPS_LIMIT: u32 = 64;
pub const OUT_LEFT: u32 = 1;
pub const OUT_RIGHT: u32 = 2;
pub const OUT_TOP: u32 = 4;
pub const OUT_BOTTOM: u32 = 8;
pub const OUT_BEHIND: u32 = 16;

/// A parameter rectangle of one object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    pub u: [f32; 2],
    pub v: [f32; 2],
    pub object: u32,
}

/// Largest pre-split per side ([`Patch::pre_split`]).
pub const MAX_PRE_SPLIT: u32 = 16;

impl Patch {
    pub fn new(u: [f32; 2], v: [f32; 2], object: u32) -> Patch {
        Patch { u, v, object }
    }

    /// The whole domain of an object: PATCH INITIALIZATION for one object.
    pub fn from_domain(domain: &ParamDomain, object: u32) -> Patch {
        Patch::new(domain.u, domain.v, object)
    }

    /// The patch cut into `k × k` equal patches (PATCH INITIALIZATION's optional uniform
    /// pre-split for objects known to be detailed), `k` a power of two up to
    /// [`MAX_PRE_SPLIT`] so that the cut points `u0 + (u1 - u0) · (i · (1/k))` are computed
    /// alike by any IEEE f32 arithmetic (1/k and i/k exact; no fused multiply-add). Neighbours
    /// share their cut exactly and the outer ends are the patch's own.
    pub fn pre_split(&self, k: u32) -> Result<Vec<Patch>> {
        if !k.is_power_of_two() || k > MAX_PRE_SPLIT {
            return Err(DataError::Invalid(format!(
                "pre-split {k}: must be a power of two from 1 to {MAX_PRE_SPLIT}"
            )));
        }
        let cut = |r: [f32; 2], i: u32| match i {
            0 => r[0],
            i if i == k => r[1],
            i => r[0] + (r[1] - r[0]) * (i as f32 * (1.0 / k as f32)),
        };
        Ok((0..k * k)
            .map(|c| {
                let (i, j) = (c % k, c / k);
                Patch::new(
                    [cut(self.u, i), cut(self.u, i + 1)],
                    [cut(self.v, j), cut(self.v, j + 1)],
                    self.object,
                )
            })
            .collect())
    }

    pub fn area(&self) -> f64 {
        (f64::from(self.u[1]) - f64::from(self.u[0]))
            * (f64::from(self.v[1]) - f64::from(self.v[0]))
    }

    fn validate(&self, index: usize) -> Result<()> {
        let ok = |r: [f32; 2]| {
            r[0].is_finite() && r[1].is_finite() && r[0] < r[1] && (r[1] - r[0]).is_finite()
        };
        if !ok(self.u) || !ok(self.v) {
            return Err(DataError::Invalid(format!(
                "patch {index}: ranges must be finite and increasing, got u = {:?}, v = {:?}",
                self.u, self.v
            )));
        }
        Ok(())
    }
}

/// Settings of the PATCH SUBDIVISION stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LodConfig {
    /// Viewport size `(W, H)` in pixels.
    pub viewport: Vec2,
    /// `(t_u, t_v)` in pixels.
    pub thresholds: Vec2,
    /// `n`, the number of LOD steps.
    pub max_steps: u32,
    pub frustum_culling: bool,
    /// Most patches one step may hold or the output may reach; exceeding it is an error rather
    /// than an unbounded allocation (4^12 patches would be 16.7 M).
    pub max_patches: usize,
}

impl LodConfig {
    /// Paper defaults: `t_u = t_v = 84`, 12 steps, culling on, at most 4 Mi patches.
    pub fn new(viewport: Vec2) -> LodConfig {
        LodConfig {
            viewport,
            thresholds: Vec2::splat(DEFAULT_THRESHOLD),
            max_steps: DEFAULT_MAX_STEPS,
            frustum_culling: true,
            max_patches: 1 << 22,
        }
    }

    fn validate(&self) -> Result<()> {
        let positive = |v: Vec2| v.is_finite() && v.x > 0.0 && v.y > 0.0;
        if !positive(self.viewport) || !positive(self.thresholds) {
            return Err(DataError::Invalid(format!(
                "LOD viewport and thresholds must be finite and positive, got {} and {}",
                self.viewport, self.thresholds
            )));
        }
        if self.max_steps == 0 || self.max_steps > MAX_STEPS_LIMIT || self.max_patches == 0 {
            return Err(DataError::Invalid(format!(
                "LOD needs 1..={MAX_STEPS_LIMIT} steps and room for a patch, got {} steps, {} patches",
                self.max_steps, self.max_patches
            )));
        }
        Ok(())
    }
}

/// The parameters of a patch's 89 samples (see the module doc), as `(u, v)`.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleParams {
    pub u_lines: [[Vec2; 8]; 4],
    pub v_lines: [[Vec2; 8]; 4],
    pub grid: [Vec2; 25],
}

pub fn sample_params(patch: &Patch) -> SampleParams {
    let [u0, u1] = patch.u;
    let [v0, v1] = patch.v;
    let (du, dv) = (u1 - u0, v1 - v0);
    let (step_u, step_v) = (du / 7.0, dv / 7.0);
    let (quarter_u, quarter_v) = (du * 0.25, dv * 0.25);
    let mut out = SampleParams {
        u_lines: [[Vec2::ZERO; 8]; 4],
        v_lines: [[Vec2::ZERO; 8]; 4],
        grid: [Vec2::ZERO; 25],
    };
    for k in 0..4 {
        let across = k as f32 + 0.5;
        for i in 0..8 {
            let along = i as f32;
            out.u_lines[k][i] = Vec2::new(u0 + step_u * along, v0 + quarter_v * across);
            out.v_lines[k][i] = Vec2::new(u0 + quarter_u * across, v0 + step_v * along);
        }
    }
    for b in 0..5 {
        for a in 0..5 {
            // max/min rather than clamp, which panics on an inverted range.
            let u = (u0 + quarter_u * a as f32).max(u0).min(u1);
            let v = (v0 + quarter_v * b as f32).max(v0).min(v1);
            out.grid[5 * b + a] = Vec2::new(u, v);
        }
    }
    out
}

/// Everything one LOD step computes for one patch.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchEvaluation {
    /// Projected samples, `None` behind the camera.
    pub u_lines: [[Option<Vec2>; 8]; 4],
    pub v_lines: [[Option<Vec2>; 8]; 4],
    pub grid: [Option<Vec2>; 25],
    /// `e_u` per u-line and `e_v` per v-line, in pixels.
    pub extents_u: [f32; 4],
    pub extents_v: [f32; 4],
    /// AND of all 89 outcodes; non-zero means the patch is off screen.
    pub outcode_and: u32,
    /// The pattern from the raw flags, before the `f32` resolution fallback.
    pub pattern: SplitPattern,
}

impl PatchEvaluation {
    pub fn split_u_lines(&self, config: &LodConfig) -> [bool; 4] {
        self.extents_u.map(|e| e > config.thresholds.x)
    }

    pub fn split_v_lines(&self, config: &LodConfig) -> [bool; 4] {
        self.extents_v.map(|e| e > config.thresholds.y)
    }

    /// `(max e_u, max e_v)`.
    pub fn max_extent(&self) -> Vec2 {
        Vec2::new(max4(self.extents_u), max4(self.extents_v))
    }
}

fn max4(e: [f32; 4]) -> f32 {
    e[0].max(e[1]).max(e[2]).max(e[3])
}

/// Samples, measures and classifies one patch (one LOD step without the bookkeeping).
pub fn evaluate_patch<S, P>(
    patch: &Patch,
    surface: &S,
    project: &P,
    config: &LodConfig,
) -> PatchEvaluation
where
    S: Fn(u32, f32, f32) -> Vec3,
    P: Fn(Vec3) -> Option<Vec2>,
{
    let params = sample_params(patch);
    let screen = |uv: Vec2| project(surface(patch.object, uv.x, uv.y)).filter(|p| !p.is_nan());
    let u_lines = params.u_lines.map(|line| line.map(screen));
    let v_lines = params.v_lines.map(|line| line.map(screen));
    let grid = params.grid.map(screen);
    let extents_u = u_lines.map(|line| line_extent(&line, config.viewport));
    let extents_v = v_lines.map(|line| line_extent(&line, config.viewport));
    let outcode_and = u_lines
        .iter()
        .chain(v_lines.iter())
        .flatten()
        .chain(grid.iter())
        .fold(u32::MAX, |acc, p| acc & outcode(*p, config.viewport));
    let mut eval = PatchEvaluation {
        u_lines,
        v_lines,
        grid,
        extents_u,
        extents_v,
        outcode_and,
        pattern: SplitPattern::Keep,
    };
    eval.pattern = SplitPattern::decide(eval.split_u_lines(config), eval.split_v_lines(config));
    eval
}

fn line_extent(line: &[Option<Vec2>; 8], viewport: Vec2) -> f32 {
    let clamp = |p: Vec2| Vec2::new(p.x.max(0.0).min(viewport.x), p.y.max(0.0).min(viewport.y));
    let mut sum = 0.0_f32;
    for pair in line.windows(2) {
        if let (Some(a), Some(b)) = (pair[0], pair[1]) {
            let (a, b) = (clamp(a), clamp(b));
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            sum += (dx * dx + dy * dy).sqrt();
        }
    }
    sum
}

fn outcode(p: Option<Vec2>, viewport: Vec2) -> u32 {
    match p {
        None => OUT_BEHIND,
        Some(p) => {
            (if p.x < 0.0 { OUT_LEFT } else { 0 })
                | (if p.x > viewport.x { OUT_RIGHT } else { 0 })
                | (if p.y < 0.0 { OUT_TOP } else { 0 })
                | (if p.y > viewport.y { OUT_BOTTOM } else { 0 })
        }
    }
}

/// A patch in "patches to render".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderPatch {
    pub patch: Patch,
    /// `(e_u, e_v)`: measured maxima, or the estimate of the module doc for forced children.
    pub extent: Vec2,
    /// The LOD step (0-based) that emitted it.
    pub step: u32,
    /// Its extents may exceed the thresholds: the step limit or `f32` resolution stopped it.
    pub over_threshold: bool,
}

/// Result of [`run_lod`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LodOutput {
    pub render: Vec<RenderPatch>,
    /// Patches evaluated in each of the `n` steps (0 once the work runs out), as in Figs. 9f–i.
    pub evaluated_per_step: Vec<usize>,
    pub culled: usize,
    /// Patches rendered unfinished because step `n` was reached.
    pub limit_hits: usize,
    /// Patches rendered unfinished because their ranges could not be halved in `f32`.
    pub resolution_hits: usize,
}

impl LodOutput {
    pub fn hit_iteration_limit(&self) -> bool {
        self.limit_hits > 0
    }
}

enum Outcome {
    Culled,
    Render(RenderPatch, bool),
    Split(Vec<(Patch, Vec2)>),
}

/// Runs the PATCH SUBDIVISION stage on `patches` (see the module doc for the rules).
pub fn run_lod<S, P>(
    patches: &[Patch],
    surface: S,
    project: P,
    config: &LodConfig,
) -> Result<LodOutput>
where
    S: Fn(u32, f32, f32) -> Vec3 + Sync,
    P: Fn(Vec3) -> Option<Vec2> + Sync,
{
    config.validate()?;
    for (i, p) in patches.iter().enumerate() {
        p.validate(i)?;
    }
    check_capacity(patches.len(), config)?;
    let mut out = LodOutput {
        evaluated_per_step: vec![0; config.max_steps as usize],
        ..LodOutput::default()
    };
    let mut current = patches.to_vec();
    for step in 0..config.max_steps {
        out.evaluated_per_step[step as usize] = current.len();
        if current.is_empty() {
            continue;
        }
        let last = step + 1 == config.max_steps;
        let outcomes: Vec<Outcome> = current
            .par_iter()
            .map(|p| lod_step(p, &surface, &project, config, step))
            .collect();
        let mut next = Vec::new();
        for outcome in outcomes {
            match outcome {
                Outcome::Culled => out.culled += 1,
                Outcome::Render(r, resolution_limited) => {
                    out.resolution_hits += usize::from(resolution_limited);
                    out.render.push(r);
                }
                Outcome::Split(children) if last => {
                    out.limit_hits += children.len();
                    out.render
                        .extend(children.into_iter().map(|(patch, extent)| RenderPatch {
                            patch,
                            extent,
                            step,
                            over_threshold: true,
                        }));
                }
                Outcome::Split(children) => next.extend(children.into_iter().map(|(p, _)| p)),
            }
        }
        check_capacity(next.len().max(out.render.len()), config)?;
        current = next;
    }
    Ok(out)
}

fn check_capacity(count: usize, config: &LodConfig) -> Result<()> {
    if count > config.max_patches {
        return Err(DataError::Invalid(format!(
            "LOD produced {count} patches, more than the configured maximum of {}",
            config.max_patches
        )));
    }
    Ok(())
}

fn lod_step<S, P>(patch: &Patch, surface: &S, project: &P, config: &LodConfig, step: u32) -> Outcome
where
    S: Fn(u32, f32, f32) -> Vec3,
    P: Fn(Vec3) -> Option<Vec2>,
{
    let eval = evaluate_patch(patch, surface, project, config);
    if config.frustum_culling && eval.outcode_and != 0 {
        return Outcome::Culled;
    }
    let mut su = eval.split_u_lines(config);
    let mut sv = eval.split_v_lines(config);
    let requested = su.iter().chain(sv.iter()).any(|&f| f);
    // A range f32 cannot halve drops its own requests; the other direction then splits whole,
    // since isolating one half would need the impossible cut.
    if !halvable(patch.u) {
        su = [false; 4];
        if sv.iter().any(|&f| f) {
            sv = [true; 4];
        }
    }
    if !halvable(patch.v) {
        sv = [false; 4];
        if su.iter().any(|&f| f) && halvable(patch.u) {
            su = [true; 4];
        }
    }
    let pattern = SplitPattern::decide(su, sv);
    if pattern == SplitPattern::Keep {
        let render = RenderPatch {
            patch: *patch,
            extent: eval.max_extent(),
            step,
            over_threshold: requested,
        };
        return Outcome::Render(render, requested);
    }
    let children = pattern
        .pieces()
        .iter()
        .map(|&(pu, pv)| {
            let child = Patch::new(part(patch.u, pu), part(patch.v, pv), patch.object);
            (child, child_extent(&eval, pu, pv))
        })
        .collect();
    Outcome::Split(children)
}

/// Estimated extents of a child: the parent's maxima over the lines inside it, halved along a
/// halved direction (u-lines 0–1 lie in the lower v half, 2–3 in the upper; likewise v-lines).
fn child_extent(eval: &PatchEvaluation, pu: u8, pv: u8) -> Vec2 {
    let pick = |e: [f32; 4], which: u8| match which {
        0 => e[0].max(e[1]),
        1 => e[2].max(e[3]),
        _ => max4(e),
    };
    let halve = |which: u8| if which == 2 { 1.0 } else { 0.5 };
    Vec2::new(
        pick(eval.extents_u, pv) * halve(pu),
        pick(eval.extents_v, pu) * halve(pv),
    )
}

#[cfg(test)]
#[path = "lod_tests.rs"]
mod tests;
