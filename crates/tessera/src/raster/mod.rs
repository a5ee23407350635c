//! The shared compute rasterizer: draws clip-space triangles made by a compute pass into a
//! depth-and-payload frame with 64-bit atomics, for techniques that avoid the graphics stages
//! (on H100/H200 a fragment shader runs far slower than the same compute shader;
//! docs/BENCHMARKS.md). A technique generates triangles, rasterizes them here, then resolves the
//! frame to colour with its own shader, which looks up what it needs by triangle index.
//!
//! The rules are those of the CPU reference [`tessera_data::rasterize`]: clipping in clip space
//! against w > 0, the near (z >= 0) and far (z <= w) planes and a guard band, fan drawing,
//! positions snapped to 1/256 pixel, pixel centres, the top-left rule, double-sided (unless a
//! frame leaves one winding out, [`RasterFrame::hide_winding`]), NDC depth
//! linear in screen space tested LESS against 1.0. Coverage uses exact integer edge functions,
//! and positions are snapped in double-float arithmetic so that they land on the reference's
//! (f64) grid points, so the frame equals
//! [`tessera_data::rasterize::rasterize_clip_triangles`] except where f32 clipping moves a
//! clipped corner to a neighbouring grid point or two depths tie within f32 rounding (neither
//! happened in the tests, on lavapipe or an H100). The far plane is clipped like the others; only
//! dropping fragments with depth >= 1 would give the same pixels in exact arithmetic (the part of
//! a triangle with z <= w is where its screen-linear depth is <= 1), but differ within a
//! sub-pixel step of that line, where the reference snaps the clipped corners.
//!
//! One invocation handles one triangle, which suits the small triangles of marching cubes; a
//! triangle covering much of the screen is drawn by a single invocation, slowly.
//!
//! # Data layout
//!
//! * **Triangles** — a storage buffer of [`RasterTriangle`], GLSL
//!   `struct RasterTriangle { vec4 clip[3]; }` (48 bytes, clip-space corners), from offset 0
//!   with nothing before them. Only the first `min(triangle_count, buffer size / 48)` are read.
//! * **Counts** — a 16-byte buffer, [`RasterCounts`]: `uint triangle_count` (written by the
//!   generating pass) then `uint dispatch[3]`, the indirect dispatch
//!   arguments [`ComputeRasterizer::record_prepare_dispatch`] fills. Usage must include
//!   `STORAGE_BUFFER | INDIRECT_BUFFER` ([`create_counts_buffer`] makes one).
//! * **Frame** — [`RasterFrame`]: `uint64_t depth_payload[width * height]`, row-major from the
//!   top-left pixel. A drawn pixel holds `floatBitsToUint(depth) << 32 | index` with `depth` the
//!   NDC depth in `[0, 1)` (a non-negative float, so its bits order as the values do) and
//!   `index` the triangle's position in the triangle buffer plus the raster pass's index base
//!   (0 unless given to [`ComputeRasterizer::record_raster_with_base`], which lets triangles
//!   from several buffers share one frame); an empty pixel holds [`EMPTY`]
//!   (all ones). Resolve shaders `#include "raster/raster.glsl"` and bind it as
//!   `uvec2 depth_payload[]` (x = index, y = depth bits) with the helpers there:
//!   `raster_is_empty`, `raster_depth`, `raster_index`, `raster_pixel_centre` and
//!   `raster_barycentrics` (perspective-correct weights of the original corners at a pixel).
//!
//! * **Drawn tiles** — `RasterFrame::tile_frames`: per tile of `RASTER_TILE` × `RASTER_TILE`
//!   pixels (row-major, `ceil(width / RASTER_TILE)` a row), the number of the last frame whose
//!   raster pass drew a triangle whose pixel box reaches into the tile. A resolve that reads
//!   only the tiles of its frame's number and empties each pixel it read (the surface draws'
//!   resolve, `iso/direct/resolve.rs`) leaves the whole frame empty, so the next frame needs no
//!   fill: the fill of every pixel and the reads of pixels nothing was drawn to are then left
//!   out (at 3840×2160 the fill alone writes 66 MB).
//!
//! # Passes
//!
//! [`RasterFrame::record_begin`] (it fills the frame only when something drawn into it was not
//! emptied by such a resolve) or [`ComputeRasterizer::record_clear`], then (after the pass that
//! writes the triangles and the count, and a barrier)
//! [`ComputeRasterizer::record_prepare_dispatch`] and [`ComputeRasterizer::record_raster`]; or
//! clear and both with [`ComputeRasterizer::record`]. Each `record_*` of the rasterizer ends
//! with a barrier, so the next pass sees its writes. A pass that makes triangles may also draw
//! them itself, with `raster/raster_draw.glsl` and the parameters
//! [`RasterFrame::record_pass_params`] writes, leaving out the raster pass.

pub mod hzb;
pub(crate) mod indirect;

pub use indirect::IndirectArgs;

use crate::builtin_shader;
use crate::error::{check_image_size, Error, Result};
use bytemuck::{Pod, Zeroable};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};
use tessera_data::rasterize::{ScreenWinding, GUARD_BAND, MIN_W, SUBPIXEL_BITS};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// The next [`RasterFrame`]'s serial number.
static NEXT_FRAME_SERIAL: AtomicU64 = AtomicU64::new(0);

/// Bytes per [`RasterTriangle`].
pub const TRIANGLE_BYTES: u64 = 48;
/// Bytes of the counts buffer ([`RasterCounts`]).
pub const COUNTS_BYTES: u64 = 16;
/// The value of a pixel nothing was drawn to.
pub const EMPTY: u64 = u64::MAX;
/// Bytes of [`RasterParams`] in a buffer ([`RasterFrame::record_pass_params`]).
pub const RASTER_PASS_PARAMS_BYTES: u64 = std::mem::size_of::<RasterParams>() as u64;
/// Pixels per side of the tiles the raster pass marks as drawn into ([`RasterFrame`]).
pub const RASTER_TILE: u32 = 8;
/// Largest frame side: keeps the guard band's snapped coordinates below 2^24 sub-pixels, where
/// the shader's snapping and 32-bit positions are exact.
pub const MAX_FRAME_SIDE: u32 = 8192;

/// One input triangle: its corners in clip space (`RasterTriangle` in `raster/raster.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RasterTriangle {
    pub clip: [[f32; 4]; 3],
}

/// The counts buffer: the triangle count, then the raster pass's indirect dispatch arguments.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct RasterCounts {
    pub triangle_count: u32,
    pub dispatch: [u32; 3],
}

/// Push constants of `raster.comp.glsl`; also what a pass that draws its own triangles
/// (`raster/raster_draw.glsl`) reads from a buffer ([`RasterFrame::record_pass_params`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct RasterParams {
    pub(crate) size: [u32; 2],
    pub(crate) capacity: u32,
    pub(crate) index_base: u32,
    /// Marked into the tiles the pass draws into ([`RasterFrame::frame_number`]).
    pub(crate) frame_number: u32,
    /// 1 or -1: the sign of the snapped area of triangles that draw nothing; 0: none
    /// ([`RasterFrame::hide_winding`]).
    pub(crate) hidden_winding: i32,
}

/// Splits a frame value into (NDC depth, triangle index); `None` for an empty pixel.
pub fn decode(value: u64) -> Option<(f32, u32)> {
    (value >> 32 != u64::from(u32::MAX))
        .then(|| (f32::from_bits((value >> 32) as u32), value as u32))
}

/// A counts buffer with the usage the passes need (storage, indirect, transfer).
pub fn create_counts_buffer(gpu: &Gpu, name: &str) -> Result<Buffer> {
    Ok(gpu.create_buffer(
        name,
        COUNTS_BYTES,
        vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?)
}

/// The rasterizer's output: one 64-bit depth-and-payload value per pixel, and per tile the
/// number of the last frame that drew into it (see the module's data layout).
pub struct RasterFrame {
    pub depth_payload: Buffer,
    pub tile_frames: Buffer,
    pub width: u32,
    pub height: u32,
    /// Which of the process's `RasterFrame`s this is: with [`Self::frame_number`], it names one
    /// frame drawn in one of them ([`Self::frame_stamp`]).
    serial: u64,
    /// The number of the frame being drawn (0 before the first).
    frame_number: Cell<u32>,
    /// Whether, after the commands recorded so far, every pixel is empty: false once something
    /// is drawn, true again after a fill or an emptying resolve.
    empty: Cell<bool>,
    /// Whether resolves leave the drawn pixels in place (see [`Self::keep_after_resolve`]).
    kept: Cell<bool>,
    /// The winding of the triangles the frame's raster passes leave out.
    hidden_winding: Cell<Option<ScreenWinding>>,
}

impl RasterFrame {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Result<RasterFrame> {
        check_image_size(width, height)?;
        if width > MAX_FRAME_SIDE || height > MAX_FRAME_SIDE {
            return Err(Error::Invalid(format!(
                "raster frame {width}x{height} is larger than {MAX_FRAME_SIDE} pixels a side"
            )));
        }
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let depth_payload = gpu.create_buffer(
            "raster depth_payload",
            width as u64 * height as u64 * 8,
            usage,
            MemoryLocation::GpuOnly,
        )?;
        let tiles =
            u64::from(width.div_ceil(RASTER_TILE)) * u64::from(height.div_ceil(RASTER_TILE));
        let tile_frames = gpu.create_buffer(
            "raster tile_frames",
            tiles * 4,
            usage,
            MemoryLocation::GpuOnly,
        )?;
        Ok(RasterFrame {
            depth_payload,
            tile_frames,
            width,
            height,
            serial: NEXT_FRAME_SERIAL.fetch_add(1, Ordering::Relaxed),
            frame_number: Cell::new(0),
            empty: Cell::new(false),
            kept: Cell::new(false),
            hidden_winding: Cell::new(None),
        })
    }

    /// Records the fill that empties every pixel, without a barrier: for callers that reset
    /// other buffers at the same time and end the lot with one barrier.
    pub fn record_fill_empty(&self, rec: &Recorder) {
        rec.fill_buffer(&self.depth_payload, u32::MAX);
        self.empty.set(true);
    }

    /// Records the start of a frame, without a barrier: the fill that empties every pixel
    /// (and the tiles' frame numbers) unless an emptying resolve already left the frame empty,
    /// and a new frame number for the raster passes to mark their tiles with. Returns whether
    /// it recorded the fill (a barrier must then follow before drawing).
    pub fn record_begin(&self, rec: &Recorder) -> bool {
        let fill = !self.empty.get();
        if fill {
            rec.fill_buffer(&self.tile_frames, 0);
            self.record_fill_empty(rec);
        }
        self.frame_number
            .set(self.frame_number.get().wrapping_add(1).max(1));
        fill
    }

    /// This frame object and the frame last begun in it: equal stamps at two times mean no
    /// frame was begun in it between them.
    pub fn frame_stamp(&self) -> (u64, u32) {
        (self.serial, self.frame_number.get())
    }

    /// Leaves out of the frame's raster passes recorded after this (until it is called
    /// again; `None`, the start, draws both sides) every triangle of `winding` on screen, as
    /// [`tessera_data::rasterize::rasterize_clip_triangles_hiding`] does: for a closed surface
    /// whose hidden side [`tessera_data::facing::hidden_winding`] found, the same frame from
    /// about half the triangles.
    pub fn hide_winding(&self, winding: Option<ScreenWinding>) {
        self.hidden_winding.set(winding);
    }

    /// The winding the frame's raster passes leave out.
    pub fn hidden_winding(&self) -> Option<ScreenWinding> {
        self.hidden_winding.get()
    }

    /// How a pass draws triangles `index_base + i` (i below `capacity`) into the frame, as
    /// things stand now.
    pub(crate) fn pass_params(&self, capacity: u32, index_base: u32) -> RasterParams {
        RasterParams {
            size: [self.width, self.height],
            capacity,
            index_base,
            frame_number: self.frame_number(),
            hidden_winding: match self.hidden_winding.get() {
                None => 0,
                Some(ScreenWinding::Positive) => 1,
                Some(ScreenWinding::Negative) => -1,
            },
        }
    }

    /// Writes into `params` (at least [`RASTER_PASS_PARAMS_BYTES`], a transfer destination)
    /// what a pass that draws its own triangles `index_base + i` into the frame reads, and notes
    /// that one is recorded next; a barrier must follow before that pass.
    pub(crate) fn record_pass_params(
        &self,
        rec: &Recorder,
        params: &Buffer,
        capacity: u32,
        index_base: u32,
    ) {
        rec.update_buffer(
            params,
            bytemuck::bytes_of(&self.pass_params(capacity, index_base)),
        );
        self.note_drawn();
    }

    /// The number the raster passes of the frame being drawn mark their tiles with.
    pub fn frame_number(&self) -> u32 {
        self.frame_number.get()
    }

    /// Notes that a raster pass was recorded into the frame.
    pub(crate) fn note_drawn(&self) {
        self.empty.set(false);
    }

    /// Notes that a resolve recorded after the frame's raster passes empties every pixel it
    /// read: the frame is empty again once it ran.
    pub(crate) fn note_emptied(&self) {
        self.empty.set(true);
    }

    /// With `keep`, resolves leave the drawn pixels in the frame, for tests and tools that read
    /// it after a draw ([`Self::read`]); every frame then begins with a fill.
    pub fn keep_after_resolve(&self, keep: bool) {
        self.kept.set(keep);
    }

    /// Whether resolves are to empty the pixels they read.
    pub(crate) fn emptied_by_resolve(&self) -> bool {
        !self.kept.get()
    }

    /// The index in [`Self::tile_frames`] of the tile holding pixel (`x`, `y`), as the shaders
    /// compute it (`raster_tile_index` in raster.glsl).
    pub fn tile_index(&self, x: u32, y: u32) -> usize {
        let tiles_per_row = self.width.div_ceil(RASTER_TILE) as usize;
        (y / RASTER_TILE) as usize * tiles_per_row + (x / RASTER_TILE) as usize
    }

    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The frame's values, row-major; see [`decode`].
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<u64>> {
        Ok(gpu.read_elements(&self.depth_payload, self.pixel_count())?)
    }
}

pub struct ComputeRasterizer {
    prepare: IndirectArgs,
    raster: Pipeline,
}

/// The reference's constants, defined once in tessera_data.
/// Pixels each invocation of a resolve pass (`iso/direct/resolve.comp.glsl`) shades, along
/// its row.
pub const RESOLVE_PIXELS: u32 = 4;

/// Workgroups of a resolve pass over a `width`×`height` frame whose workgroups have
/// `group_size` invocations: one row segment of `RESOLVE_PIXELS × group_size` pixels each.
pub fn resolve_groups(width: u32, height: u32, group_size: u32) -> [u32; 3] {
    [width.div_ceil(RESOLVE_PIXELS * group_size), height, 1]
}

/// Invocations per workgroup of the raster pass (one triangle each).
pub const RASTER_GROUP_SIZE: u32 = 64;

/// Defines of the raster pass, and of the passes that write its dispatch arguments as they
/// fill a triangle list.
pub(crate) fn raster_defines() -> Vec<(String, String)> {
    vec![
        ("RASTER_GROUP_SIZE".into(), format!("{RASTER_GROUP_SIZE}u")),
        ("SUBPIXEL_BITS".into(), SUBPIXEL_BITS.to_string()),
        ("MIN_W".into(), format!("{:?}", MIN_W as f32)),
        ("GUARD_BAND".into(), format!("{:?}", GUARD_BAND as f32)),
        ("RASTER_TILE".into(), format!("{RASTER_TILE}u")),
    ]
}

/// Ways the rasterizer may draw, for performance work (`tessera bench isosurface
/// --ablations`): the exact one every renderer uses, candidates that draw the same frames,
/// and stages left out, whose frames are wrong, to tell where the time goes where no profiler
/// reads the GPU's counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum RasterVariant {
    #[default]
    Exact,
    /// Exact, each fragment's atomic left out where a relaxed read of the pixel already holds a
    /// value at or below its own.
    ReadBeforeAtomic,
    /// Exact; a triangle whose pixel box holds more than `above` pixels (and whose box is under
    /// 2^15 sub-pixels a side) is walked by its invocation's whole subgroup, neighbouring
    /// invocations taking neighbouring pixels. Needs subgroup ballot and shuffle
    /// ([`RasterVariant::available`]).
    SubgroupWalk { above: u32 },
    /// Fragments computed but never written.
    NoAtomics,
    /// Triangles clipped, snapped and set up, their tiles marked; no pixel visited.
    SetupOnly,
    /// No triangle read or drawn: what the extraction costs alone.
    NoDraw,
}

impl RasterVariant {
    pub const ALL: [RasterVariant; 7] = [
        RasterVariant::Exact,
        RasterVariant::ReadBeforeAtomic,
        RasterVariant::SubgroupWalk { above: 16 },
        RasterVariant::SubgroupWalk { above: 64 },
        RasterVariant::NoAtomics,
        RasterVariant::SetupOnly,
        RasterVariant::NoDraw,
    ];

    pub fn name(self) -> String {
        match self {
            RasterVariant::Exact => "exact".into(),
            RasterVariant::ReadBeforeAtomic => "read before atomic".into(),
            RasterVariant::SubgroupWalk { above } => format!("subgroup walk above {above} px"),
            RasterVariant::NoAtomics => "no atomics".into(),
            RasterVariant::SetupOnly => "set-up only".into(),
            RasterVariant::NoDraw => "no drawing".into(),
        }
    }

    /// Whether its frames are the exact ones.
    pub fn is_exact(self) -> bool {
        matches!(
            self,
            RasterVariant::Exact
                | RasterVariant::ReadBeforeAtomic
                | RasterVariant::SubgroupWalk { .. }
        )
    }

    /// Whether `gpu` can draw this way.
    pub fn available(self, gpu: &Gpu) -> bool {
        match self {
            RasterVariant::SubgroupWalk { .. } => gpu.caps().subgroup_ballot_and_shuffle,
            _ => true,
        }
    }

    /// The defines `raster/raster_draw.glsl` reads: `RASTER_VARIANT`, and for the subgroup
    /// walk `RASTER_SUBGROUP_WALK` and `RASTER_SUBGROUP_WALK_ABOVE`.
    pub(crate) fn defines(self) -> Vec<(String, String)> {
        let code = match self {
            RasterVariant::Exact | RasterVariant::SubgroupWalk { .. } => 0,
            RasterVariant::ReadBeforeAtomic => 1,
            RasterVariant::NoAtomics => 2,
            RasterVariant::SetupOnly => 3,
            RasterVariant::NoDraw => 4,
        };
        let above = match self {
            RasterVariant::SubgroupWalk { above } => Some(above),
            _ => None,
        };
        vec![
            ("RASTER_VARIANT".into(), code.to_string()),
            (
                "RASTER_SUBGROUP_WALK".into(),
                u32::from(above.is_some()).to_string(),
            ),
            (
                "RASTER_SUBGROUP_WALK_ABOVE".into(),
                format!("{}", above.unwrap_or(0)),
            ),
        ]
    }
}

impl ComputeRasterizer {
    /// Builds the passes; the device must have 64-bit buffer atomics
    /// (`caps().buffer_int64_atomics`).
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<ComputeRasterizer> {
        Self::with_variant(gpu, compiler, RasterVariant::Exact)
    }

    /// Builds the passes drawing as `variant` says.
    pub fn with_variant(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        variant: RasterVariant,
    ) -> Result<ComputeRasterizer> {
        if !gpu.caps().buffer_int64_atomics {
            return Err(Error::Invalid(format!(
                "the compute rasterizer needs 64-bit buffer atomics, which {} lacks",
                gpu.caps().device_name
            )));
        }
        if !variant.available(gpu) {
            return Err(Error::Invalid(format!(
                "the rasterizer's {} needs subgroup ballot and shuffle, which {} lacks",
                variant.name(),
                gpu.caps().device_name
            )));
        }
        let mut defines = raster_defines();
        defines.extend(variant.defines());
        let raster = compiler.compile(&builtin_shader!("raster.comp.glsl"), &defines)?;
        let raster = gpu.compute_pipeline("raster", &raster, &[Slot::StorageBuffer; 4])?;
        let prepare = IndirectArgs::new(gpu, compiler)?;
        Ok(ComputeRasterizer { prepare, raster })
    }

    /// Lowers the workgroups per row of the raster dispatch (never above the device's limit),
    /// so that tests can reach the 2-D grid with few triangles.
    pub fn limit_groups_x(&mut self, groups: u32) {
        self.prepare.max_groups[0] = groups.clamp(1, self.prepare.max_groups[0]);
    }

    /// Invocations (triangles) per workgroup of the raster pass.
    pub fn group_size(&self) -> u32 {
        self.raster.local_size[0]
    }

    /// Marks every pixel of `frame` empty.
    pub fn record_clear(&self, rec: &Recorder, frame: &RasterFrame) {
        frame.record_fill_empty(rec);
        rec.barrier();
    }

    /// Writes the raster pass's dispatch arguments into `counts` from its triangle count.
    pub fn record_prepare_dispatch(&self, rec: &Recorder, counts: &Buffer) {
        self.prepare.record(rec, counts, self.group_size());
    }

    /// Draws the counted triangles into `frame`, keeping the nearest per pixel; `counts` must
    /// hold arguments from [`Self::record_prepare_dispatch`].
    pub fn record_raster(
        &self,
        rec: &Recorder,
        triangles: &Buffer,
        counts: &Buffer,
        frame: &RasterFrame,
    ) {
        self.record_raster_with_base(rec, triangles, counts, frame, 0);
    }

    /// Like [`Self::record_raster`], with `index_base` added to every triangle's index in the
    /// frame: triangle `i` of `triangles` is stored as `index_base + i`, so that a resolve can
    /// tell which of several buffers drawn into one frame a pixel's triangle came from. The sum
    /// must fit in 32 bits.
    pub fn record_raster_with_base(
        &self,
        rec: &Recorder,
        triangles: &Buffer,
        counts: &Buffer,
        frame: &RasterFrame,
        index_base: u32,
    ) {
        let capacity = (triangles.size / TRIANGLE_BYTES).min(u32::MAX as u64) as u32;
        let params = frame.pass_params(capacity, index_base);
        rec.dispatch_indirect(
            &self.raster,
            &[
                Binding::Buffer(triangles),
                Binding::Buffer(counts),
                Binding::Buffer(&frame.depth_payload),
                Binding::Buffer(&frame.tile_frames),
            ],
            bytemuck::bytes_of(&params),
            counts,
            4,
        );
        frame.note_drawn();
        rec.barrier();
    }

    /// Clears `frame` and draws the counted triangles into it.
    pub fn record(&self, rec: &Recorder, triangles: &Buffer, counts: &Buffer, frame: &RasterFrame) {
        self.record_clear(rec, frame);
        self.record_prepare_dispatch(rec, counts);
        self.record_raster(rec, triangles, counts, frame);
    }
}
