//! PATCH INITIALIZATION and PATCH SUBDIVISION on the GPU (paper E §4, §4.1), following the
//! rules of `tessera_data::param::lod` (the CPU reference) bit for bit given equal sample
//! positions: `precise` arithmetic in the CPU's order, and `d / 7` and the segment lengths'
//! `sqrt` corrected to correct rounding, since Vulkan allows both to be inexact (NVIDIA's are;
//! without the correction the sample parameters differed from the CPU's on an H200).
//!
//! Buffers:
//! * two evaluation lists (ping-pong: step `s` reads list `s % 2`, writes its children to the
//!   other) and the render list, each of `capacity` [`GpuPatch`]es (`Patch` in `patch.glsl`);
//! * the state buffer ([`LodStats`] header, then one `LodEntry {count, dispatch x, y, z}` per
//!   list: entry 0 the render list, entry `1 + s` the patches step `s` evaluates);
//! * optionally a capture of every LOD sample (object, u, v, pixel x, y) for tests.
//!
//! Passes: clear the state; `lod_init` (one invocation per object); then per step `lod_step`
//! dispatched indirectly, one 64-invocation workgroup per patch, from arguments the pass that
//! filled its list grew as it appended (`common/indirect_args.glsl`: no pass between steps);
//! finally `lod_prepare` for the render list, whose arguments (spread over workgroups when the
//! list is short) the point pass uses. Lists that overflow drop patches and count them.

use super::scene::{scene_defines, sh_recurrence_table, GpuParamScene};
use crate::builtin_shader;
use crate::error::{Error, Result};
use bytemuck::{Pod, Zeroable};
use tessera_data::param::SplitPattern;
use tessera_data::View;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// Bytes of the state buffer's statistics header.
const STATE_HEADER_BYTES: u64 = 32;
/// Bytes per list entry.
const ENTRY_BYTES: u64 = 16;
/// Bytes per captured sample.
pub const SAMPLE_BYTES: u64 = 20;

/// A patch as the GPU stores it (`Patch` in `patch.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuPatch {
    pub u: [f32; 2],
    pub v: [f32; 2],
    /// `(e_u, e_v)` in raster pixels.
    pub extent: [f32; 2],
    pub object: u32,
    /// LOD step | [`OVER_THRESHOLD`].
    pub info: u32,
}

/// `info` bit: the patch's extents may exceed the thresholds (step limit or f32 resolution).
pub const OVER_THRESHOLD: u32 = 1 << 16;

impl GpuPatch {
    pub fn step(&self) -> u32 {
        self.info & 0xffff
    }

    pub fn over_threshold(&self) -> bool {
        self.info & OVER_THRESHOLD != 0
    }
}

/// One captured LOD sample: `x` is NaN where the point is behind the eye.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LodSample {
    pub object: u32,
    pub u: f32,
    pub v: f32,
    pub x: f32,
    pub y: f32,
}

/// What the LOD stage (and the point pass) counted in a frame.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LodStats {
    pub culled: u32,
    pub limit_hits: u32,
    pub resolution_hits: u32,
    /// Patches lost because a list was full; non-zero means the frame is incomplete.
    pub dropped: u32,
    /// LOD samples offered to the capture (89 per evaluated patch when capturing).
    pub captured: u32,
    /// Point pass: triangles too large to rasterize.
    pub skipped_cells: u32,
    /// Patches to render (as appended; more than the capacity when `dropped`).
    pub rendered: u32,
    /// Patches evaluated by each step.
    pub evaluated_per_step: Vec<u32>,
}

/// Push constants of `lod_init` and `lod_step` (`lod_params.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LodParams {
    pub world_to_clip: [[f32; 4]; 4],
    pub viewport: [f32; 2],
    pub thresholds: [f32; 2],
    pub step: u32,
    pub last: u32,
    pub eval_capacity: u32,
    pub render_capacity: u32,
    pub culling: u32,
    pub capture_capacity: u32,
    pub object_count: u32,
    /// Each object starts as `pre_split × pre_split` patches.
    pub pre_split: u32,
}

/// Push constants of `lod_prepare.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct PrepareParams {
    pub max_groups: [u32; 2],
    pub entry: u32,
    pub capacity: u32,
    pub per_group: u32,
    /// Workgroups the pass should have at least: a list of fewer patches gets up to
    /// [`MAX_SPREAD`] workgroups per patch along z, which share the patch's tiles (0: one).
    pub spread_target: u32,
}

/// Most workgroups one patch of the render list is spread over ([`PrepareParams`]).
pub const MAX_SPREAD: u32 = 64;

/// Workgroups the point pass should have at least: far more than a GPU holds at once, so a
/// frame of a few large patches (one glyph filling the screen) still keeps every unit busy.
const POINT_PASS_GROUPS: u32 = 16384;

/// LOD settings (the CPU's `LodConfig` without the viewport, which comes from the view).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LodSettings {
    /// `(t_u, t_v)` in raster pixels.
    pub thresholds: [f32; 2],
    /// `n`, at most [`tessera_data::param::lod::MAX_STEPS_LIMIT`].
    pub max_steps: u32,
    pub frustum_culling: bool,
    /// Patches each list holds.
    pub capacity: u32,
    /// Each object starts as `k × k` patches ([`tessera_data::param::Patch::pre_split`]).
    pub pre_split: u32,
}

/// Defines of the LOD shaders: the scene layout and the split tables.
pub fn lod_defines() -> Vec<(String, String)> {
    let mut defines = scene_defines();
    defines.extend(split_defines());
    defines.push(("PARAM_MAX_SPREAD".into(), format!("{MAX_SPREAD}u")));
    defines
}

/// The `SplitPattern` tables of `lod_step.comp.glsl`, generated from the CPU's definitions.
fn split_defines() -> Vec<(String, String)> {
    let decide: Vec<String> = (0..16u32)
        .map(|f| {
            let bit = |i: u32| f & (1 << i) != 0;
            let pattern = SplitPattern::decide(
                [bit(0), false, bit(1), false],
                [bit(2), false, bit(3), false],
            );
            format!("{}u", pattern.code())
        })
        .collect();
    let unit = tessera_data::param::Patch::new([0.0, 1.0], [0.0, 1.0], 0);
    let part = |r: [f32; 2]| {
        if r == [0.0, 0.5] {
            0u32
        } else if r == [0.5, 1.0] {
            1
        } else {
            2
        }
    };
    let pieces: Vec<String> = (0..8u32)
        .map(|code| {
            let pattern = (0..16u32)
                .map(|f| {
                    let bit = |i: u32| f & (1 << i) != 0;
                    SplitPattern::decide(
                        [bit(0), false, bit(1), false],
                        [bit(2), false, bit(3), false],
                    )
                })
                .find(|p| p.code() == code)
                .unwrap_or(SplitPattern::Keep);
            let children = pattern.children(&unit);
            let mut word = (children.len() as u32) << 16;
            for (i, c) in children.iter().enumerate() {
                word |= (part(c.u) | (part(c.v) << 2)) << (4 * i);
            }
            format!("{word}u")
        })
        .collect();
    vec![
        (
            "PARAM_SPLIT_DECIDE".into(),
            format!("uint[16]({})", decide.join(",")),
        ),
        (
            "PARAM_SPLIT_PIECES".into(),
            format!("uint[8]({})", pieces.join(",")),
        ),
    ]
}

pub struct LodStage {
    init: Pipeline,
    prepare: Pipeline,
    step: Pipeline,
    pub(super) lists: [Buffer; 2],
    pub(super) render: Buffer,
    pub(super) state: Buffer,
    /// A one-sample stand-in bound when nothing is captured.
    no_capture: Buffer,
    /// The SH recurrence factors (`sh_recurrence`, binding 2 of every pass).
    pub(super) sh_table: Buffer,
    pub(super) settings: LodSettings,
    max_groups: [u32; 2],
}

impl LodStage {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, settings: LodSettings) -> Result<LodStage> {
        let limit = tessera_data::param::lod::MAX_STEPS_LIMIT;
        let t = settings.thresholds;
        if settings.max_steps == 0 || settings.max_steps > limit {
            return Err(Error::Invalid(format!(
                "LOD needs 1 to {limit} steps, got {}",
                settings.max_steps
            )));
        }
        if !(t[0] > 0.0 && t[1] > 0.0 && t[0].is_finite() && t[1].is_finite()) {
            return Err(Error::Invalid(format!(
                "LOD thresholds must be finite and positive, got {t:?}"
            )));
        }
        if settings.capacity == 0 || u64::from(settings.capacity) * 32 > u64::from(u32::MAX) {
            return Err(Error::Invalid(format!(
                "patch capacity must be 1 to {}, got {}",
                u32::MAX / 32,
                settings.capacity
            )));
        }
        let max_split = tessera_data::param::lod::MAX_PRE_SPLIT;
        let k = settings.pre_split;
        if !k.is_power_of_two() || k > max_split {
            return Err(Error::Invalid(format!(
                "pre-split {k}: must be a power of two from 1 to {max_split}"
            )));
        }
        let defines = lod_defines();
        let spirv = |source| compiler.compile(&source, &defines);
        let init = spirv(builtin_shader!("lod_init.comp.glsl"))?;
        let prepare = spirv(builtin_shader!("lod_prepare.comp.glsl"))?;
        let step = spirv(builtin_shader!("lod_step.comp.glsl"))?;
        let init = gpu.compute_pipeline("param lod init", &init, &[Slot::StorageBuffer; 5])?;
        let prepare =
            gpu.compute_pipeline("param lod prepare", &prepare, &[Slot::StorageBuffer])?;
        let step = gpu.compute_pipeline("param lod step", &step, &[Slot::StorageBuffer; 8])?;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let bytes = u64::from(settings.capacity) * std::mem::size_of::<GpuPatch>() as u64;
        let buffer = |name: &str, bytes: u64, extra| {
            gpu.create_buffer(name, bytes, usage | extra, MemoryLocation::GpuOnly)
        };
        let none = vk::BufferUsageFlags::empty();
        let state_bytes = STATE_HEADER_BYTES + ENTRY_BYTES * (u64::from(settings.max_steps) + 2);
        Ok(LodStage {
            init,
            prepare,
            step,
            lists: [
                buffer("param patches to evaluate (even steps)", bytes, none)?,
                buffer("param patches to evaluate (odd steps)", bytes, none)?,
            ],
            render: buffer("param patches to render", bytes, none)?,
            state: buffer(
                "param lod state",
                state_bytes,
                vk::BufferUsageFlags::INDIRECT_BUFFER,
            )?,
            no_capture: buffer("param lod no capture", SAMPLE_BYTES, none)?,
            sh_table: gpu.upload_buffer(
                "param sh recurrence",
                bytemuck::cast_slice(&sh_recurrence_table()),
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            settings,
            max_groups: [
                gpu.caps().max_compute_workgroup_count[0],
                gpu.caps().max_compute_workgroup_count[1],
            ],
        })
    }

    /// Bindings 0-2 of every pass: the scene's objects and values, the SH table.
    pub(super) fn scene_bindings<'a>(&'a self, scene: &'a GpuParamScene) -> [Binding<'a>; 3] {
        [
            Binding::Buffer(&scene.objects),
            Binding::Buffer(&scene.values),
            Binding::Buffer(&self.sh_table),
        ]
    }

    /// Offset of list `entry`'s indirect dispatch arguments in the state buffer.
    pub(super) fn dispatch_offset(entry: u32) -> u64 {
        STATE_HEADER_BYTES + ENTRY_BYTES * u64::from(entry) + 4
    }

    /// Writes list `entry`'s dispatch arguments, `per_group` patches per workgroup, spread
    /// over more workgroups per patch up to `spread_target` workgroups ([`PrepareParams`]).
    pub(super) fn record_prepare(
        &self,
        rec: &Recorder,
        entry: u32,
        per_group: u32,
        spread_target: u32,
    ) {
        let params = PrepareParams {
            max_groups: self.max_groups,
            entry,
            capacity: self.settings.capacity,
            per_group,
            spread_target,
        };
        rec.dispatch_groups(
            &self.prepare,
            &[Binding::Buffer(&self.state)],
            bytemuck::bytes_of(&params),
            [1, 1, 1],
        );
        rec.barrier();
    }

    /// Records initialization and every LOD step; the render list and its dispatch arguments
    /// (entry 0, one patch per workgroup) are ready afterwards. `capture` = (buffer, samples).
    pub fn record(
        &self,
        rec: &Recorder,
        scene: &GpuParamScene,
        view: &View,
        capture: Option<(&Buffer, u32)>,
    ) {
        let s = &self.settings;
        let pre_split = s.pre_split;
        let viewport = view.viewport();
        let mut params = LodParams {
            world_to_clip: view.world_to_clip.to_cols_array_2d(),
            viewport: viewport.to_array(),
            thresholds: s.thresholds,
            step: 0,
            last: 0,
            eval_capacity: s.capacity,
            render_capacity: s.capacity,
            culling: u32::from(s.frustum_culling),
            capture_capacity: capture.map_or(0, |c| c.1),
            object_count: scene.object_count,
            pre_split,
        };
        let capture_buffer = capture.map_or(&self.no_capture, |c| c.0);
        rec.fill_buffer(&self.state, 0);
        rec.barrier();
        let scene_bindings = self.scene_bindings(scene);
        rec.dispatch_groups(
            &self.init,
            &[
                scene_bindings[0],
                scene_bindings[1],
                scene_bindings[2],
                Binding::Buffer(&self.state),
                Binding::Buffer(&self.lists[0]),
            ],
            bytemuck::bytes_of(&params),
            tessera_gpu::spread_groups(
                (scene.object_count * pre_split * pre_split).div_ceil(64),
                self.max_groups[0],
            ),
        );
        rec.barrier();
        // Each step's list got its dispatch arguments from the pass that filled it.
        for step in 0..s.max_steps {
            params.step = step;
            params.last = u32::from(step + 1 == s.max_steps);
            let (input, output) = (step as usize % 2, (step as usize + 1) % 2);
            rec.dispatch_indirect(
                &self.step,
                &[
                    scene_bindings[0],
                    scene_bindings[1],
                    scene_bindings[2],
                    Binding::Buffer(&self.state),
                    Binding::Buffer(&self.lists[input]),
                    Binding::Buffer(&self.lists[output]),
                    Binding::Buffer(&self.render),
                    Binding::Buffer(capture_buffer),
                ],
                bytemuck::bytes_of(&params),
                &self.state,
                Self::dispatch_offset(1 + step),
            );
            rec.barrier();
        }
        self.record_prepare(rec, 0, 1, POINT_PASS_GROUPS);
    }

    /// Fills the patch lists with all-ones words (NaN ranges), so that a slot the passes
    /// report but never wrote is caught.
    pub fn poison(&self, gpu: &Gpu) -> Result<()> {
        gpu.submit("poison param patch lists", |rec| {
            for b in [&self.lists[0], &self.lists[1], &self.render] {
                rec.fill_buffer(b, u32::MAX);
            }
        })?;
        Ok(())
    }

    /// The counters of the last recorded frame.
    /// [`Self::read_stats`] after a frame of `technique`: a frame that lost patches to full
    /// lists is an error.
    pub fn read_frame_stats(&self, gpu: &Gpu, technique: &str) -> Result<LodStats> {
        let stats = self.read_stats(gpu)?;
        if stats.dropped > 0 {
            return Err(Error::Invalid(format!(
                "{technique} lost {} patches to full lists of {}: raise patch_capacity",
                stats.dropped, self.settings.capacity
            )));
        }
        Ok(stats)
    }

    pub fn read_stats(&self, gpu: &Gpu) -> Result<LodStats> {
        let w = gpu.read_buffer_as::<u32>(&self.state)?;
        let entry = |i: u32| w[(STATE_HEADER_BYTES / 4 + u64::from(i) * 4) as usize];
        Ok(LodStats {
            culled: w[0],
            limit_hits: w[1],
            resolution_hits: w[2],
            dropped: w[3],
            captured: w[4],
            skipped_cells: w[5],
            rendered: entry(0),
            evaluated_per_step: (0..self.settings.max_steps).map(|s| entry(1 + s)).collect(),
        })
    }

    /// The patches to render of the last recorded frame (in the GPU's arbitrary order).
    pub fn read_patches(&self, gpu: &Gpu) -> Result<Vec<GpuPatch>> {
        let count = self.read_stats(gpu)?.rendered.min(self.settings.capacity) as usize;
        Ok(gpu.read_elements(&self.render, count)?)
    }
}
