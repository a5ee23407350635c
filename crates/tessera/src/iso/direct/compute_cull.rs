//! Occlusion culling for the compute path of `direct`: temporal, conservative, with a max-depth
//! pyramid (HZB) instead of the mesh path's proxy quads. The image equals the unculled one
//! (up to triangles tying in depth, which the rasterizer breaks by index).
//!
//! A culled frame:
//! 1. **Pass A** extracts the blocks that owned a pixel last frame (a block list, one workgroup
//!    per listed block) and rasterizes them into the frame.
//! 2. A **max-depth pyramid** is built from the frame ([`crate::raster::hzb`]): level 0 at half
//!    resolution, six levels per dispatch (a workgroup folds a 32×32 tile in shared memory),
//!    so two dispatches at 3840×2160 instead of twelve.
//! 3. The **occlusion test** visits every block: those whose (min, max) holds the isovalue are
//!    counted; of those not drawn in pass A, a block is listed for pass B when its cell box
//!    reaches the near plane, or when on the pyramid level where its screen rectangle (a pixel
//!    wider on each side) spans at most 4×4 texels some texel's max depth is at or behind the
//!    box's nearest depth. Everything pass A drew lies in the final image, so a block that fails
//!    the test is hidden behind it. The box tested is the block's cells that made triangles
//!    when it was last extracted at this isovalue (each extraction records it, `cell_box.glsl`;
//!    boxes are kept per volume), else its whole cell box: on the 256³ head at 1280×720 the
//!    blocks pass B draws in a still frame went from 1,558 to 877 (the same counts on lavapipe
//!    and an H200 before the change).
//! 4. **Pass B** extracts the listed blocks into a second [`TriangleLists`] (owned by the
//!    state); a cell whose box fails the same test makes no triangles (most blocks listed in a
//!    still frame own no pixel, and most of their cells lie behind pass A's surface). It
//!    rasterizes them into the same frame with index base = pass A's capacity: a
//!    frame index `i` refers to pass A's triangle `i` below that base, to pass B's triangle
//!    `i - base` from it. The resolve reads the right list and gives the block of every drawn
//!    pixel's triangle the frame's number (the extraction tags each triangle with its block
//!    id); the first pixel to do so lists the block for next frame's pass A. Two lists rather
//!    than pass B appending to pass A's: where pass A ended is known only on the GPU, while an
//!    index base known on the host needs one push constant in the rasterizer. The price is
//!    memory: pass B's list gets the target's capacity, as the first frame (or one after
//!    [`ComputeCullState::reset`]) draws everything in view there.
//! 5. A **finishing** pass (one invocation) sizes that list's dispatch, writes the frame's
//!    counts into host-visible memory, then empties what the next frame fills: the counts,
//!    pass A's list just drawn (next frame's resolve lists into it), pass B's list, and both
//!    triangle lists' counts. A compaction over every block's flags stood here before (0.043
//!    ms of the 1024³ head's frame at 3840×2160 on an H100, run 123), and seven fills and their
//!    barrier began each frame (0.011 ms at 3840×2160 on the 256³ head, run 123). Those fills
//!    are recorded only where the last frame was not this state's in the same target
//!    (the first frame, one after a reset, or after another frame into the target: every
//!    recording that writes a target's triangle counts begins a frame in its `RasterFrame`).
//!
//! The test, which appends to a list, and the extractions, which reserve triangles, grow the
//! indirect dispatch arguments of the pass that reads them (`common/indirect_args.glsl`), so
//! no bookkeeping pass and barrier sits between them; the resolve's list is sized by the
//! finishing pass, which the frame needs anyway: at 3840×2160 the frame is 9 dispatches (23
//! with a pass per pyramid level and bookkeeping passes).
//!
//! Blocks are never marked visible without owning a pixel, so the pass-A list is exactly the
//! visible set of the last frame; a block that passes the test but owns no pixel is drawn in
//! pass B every frame (the cell boxes make those fewer).
//!
//! Frames are recorded by `DirectCompute::record_culled` (in `compute_cull_frame.rs`) with a
//! [`ComputeCullState`]; the state's statistics say what each pass drew.

use crate::builtin_shader;
use crate::error::Result;
use crate::iso::ablation::Ablation;
use crate::iso::direct::block_list;
use crate::iso::direct::cell_boxes::{cell_box_defines, CellBoxes};
use crate::iso::direct::compute::{drawing_extraction, DirectRaster};
use crate::iso::direct::compute::{extract_defines, ComputeTarget, TriangleLists};
use crate::iso::direct::resolve::SurfaceResolve;
use crate::iso::PreparedVolume;
use crate::raster::hzb::{hzb_bytes, HzbBuilder};
use crate::raster::RasterVariant;
use bytemuck::{Pod, Zeroable};
use std::cell::Cell;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::ScalarType;
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation, Pipeline, Readback, ShaderCompiler, Slot};

/// Push constants of `hzb_test.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct HzbTestParams {
    pub grid_to_clip: [[f32; 4]; 4],
    /// xyz samples per axis, w pyramid levels.
    pub dims: [u32; 4],
    /// xy frame width and height.
    pub size: [u32; 4],
    /// x the isovalue.
    pub iso: [f32; 4],
    /// The flag of the blocks pass A drew: the number of the frame before.
    pub first_pass_number: u32,
    pub pad: [u32; 3],
}

/// Workgroups for `threads` invocations of a 1-D pass as a 2-D grid within the x limit.
pub(super) fn groups_2d(threads: u32, local: u32, max_x: u32) -> [u32; 3] {
    tessera_gpu::spread_groups(threads.div_ceil(local.max(1)), max_x)
}

/// The culling pipelines, built with [`crate::iso::direct::compute::DirectCompute`].
pub(crate) struct ComputeCullPipelines {
    /// Pass A's extraction.
    pub(super) extract_list: Pipeline,
    /// Pass B's: its cells hidden behind pass A's pyramid make no triangles.
    pub(super) extract_new: Pipeline,
    /// Whether `extract_list` draws its triangles into the frame (no raster passes).
    pub(super) raster: DirectRaster,
    pub(super) hzb: HzbBuilder,
    pub(super) test: Pipeline,
    pub(super) resolve: SurfaceResolve,
    pub(super) finish: Pipeline,
    pub(super) max_groups_x: u32,
}

/// A list extraction of the culling (`extract.comp.glsl` with `BLOCK_LIST` and `defines`):
/// pass A's, or pass B's (`hidden_cells`), which leaves out hidden cells and so binds the
/// frame's buffers (`frame_bindings`, which a drawing extraction binds anyway) and the pyramid
/// after its own.
fn list_extraction(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    defines: &[(String, String)],
    (raster, variant): (DirectRaster, RasterVariant),
    hidden_cells: bool,
) -> Result<Pipeline> {
    let sb = Slot::StorageBuffer;
    let mut defines = defines.to_vec();
    defines.push(("BLOCK_LIST".into(), "1".into()));
    let mut slots = vec![Slot::Texture, sb, sb, sb, sb, sb, sb, sb];
    if hidden_cells {
        defines.push(("HIDDEN_CELLS_LEFT_OUT".into(), "1".into()));
        let frame_slots = if raster == DirectRaster::Pass { 3 } else { 0 };
        slots.extend(vec![sb; frame_slots + 1]);
    }
    let blocks = if hidden_cells {
        "new blocks"
    } else {
        "block list"
    };
    Ok(match raster {
        DirectRaster::Pass => {
            let spirv = compiler.compile(&builtin_shader!("extract.comp.glsl"), &defines)?;
            gpu.compute_pipeline(&format!("direct extract ({blocks})"), &spirv, &slots)?
        }
        DirectRaster::InExtraction => drawing_extraction(
            gpu,
            compiler,
            &defines,
            &slots,
            &format!("direct extract ({blocks}, drawing)"),
            variant,
        )?,
    })
}

/// A way of running pass A's extraction, for measuring where its time goes (`tessera bench
/// isosurface --ablations`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FirstExtractionWay {
    /// The stages left out: its triangles are then not a surface (none at all for
    /// [`Ablation::SamplesOnly`] and [`Ablation::AnalysisOnly`]).
    pub ablation: Ablation,
    /// Every corner of the block's triangles made by its own invocation (`SPREAD_CORNERS`),
    /// rather than each cell's triangles one after another by the cell's: the same triangles
    /// in the same slots, with no invocation left making a cell's ten corners while the rest
    /// wait.
    pub spread_corners: bool,
}

impl FirstExtractionWay {
    /// The ways worth timing: whole, then less and less of it ([`Ablation::DIRECT`]), then
    /// whole with its corners spread.
    pub fn all() -> Vec<FirstExtractionWay> {
        let mut ways: Vec<FirstExtractionWay> = Ablation::DIRECT
            .iter()
            .map(|&ablation| FirstExtractionWay {
                ablation,
                spread_corners: false,
            })
            .collect();
        ways.push(FirstExtractionWay {
            ablation: Ablation::None,
            spread_corners: true,
        });
        ways
    }

    pub fn name(self) -> String {
        let spread = if self.spread_corners {
            ", corners spread"
        } else {
            ""
        };
        format!("{}{spread}", self.ablation.name())
    }
}

/// Pass A's extraction run `way`, for measuring.
pub fn measured_list_extraction(
    gpu: &Gpu,
    compiler: &ShaderCompiler,
    scalar: ScalarType,
    way: FirstExtractionWay,
) -> Result<Pipeline> {
    let subgroup_scan = gpu.caps().subgroup_arithmetic;
    let mut defines = cull_defines(scalar, AmbiguityRule::default(), subgroup_scan);
    defines.push(way.ablation.define());
    if way.spread_corners {
        defines.push(("SPREAD_CORNERS".into(), "1".into()));
    }
    list_extraction(
        gpu,
        compiler,
        &defines,
        (DirectRaster::Pass, RasterVariant::Exact),
        false,
    )
}

/// The defines of the culling passes: the extraction's, and the cell boxes' layout.
pub(crate) fn cull_defines(
    scalar: ScalarType,
    rule: AmbiguityRule,
    subgroup_scan: bool,
) -> Vec<(String, String)> {
    let mut defines = extract_defines(scalar, rule, subgroup_scan);
    defines.extend(cell_box_defines());
    let empty = block_list::BlockListHeader::EMPTY;
    defines.extend([
        ("CULL_STATS_WORDS".into(), format!("{STATS_WORDS}u")),
        (
            "EXTRACT_STATS_WORDS".into(),
            format!("{EXTRACT_STATS_WORDS}u"),
        ),
        (
            "EMPTY_BLOCK_LIST".into(),
            format!(
                "BlockListHeader({}u, uint[3]({}u, {}u, {}u))",
                empty.count, empty.args[0], empty.args[1], empty.args[2]
            ),
        ),
    ]);
    defines
}

impl ComputeCullPipelines {
    pub(crate) fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        scalar: ScalarType,
        rule: AmbiguityRule,
        (raster, variant): (DirectRaster, RasterVariant),
    ) -> Result<ComputeCullPipelines> {
        let defines = cull_defines(scalar, rule, gpu.caps().subgroup_arithmetic);
        let sb = Slot::StorageBuffer;
        let test = compiler.compile(&builtin_shader!("hzb_test.comp.glsl"), &defines)?;
        let finish = compiler.compile(&builtin_shader!("cull_finish.comp.glsl"), &defines)?;
        let extract_list = list_extraction(gpu, compiler, &defines, (raster, variant), false)?;
        let extract_new = list_extraction(gpu, compiler, &defines, (raster, variant), true)?;
        let hzb = HzbBuilder::new(gpu, compiler)?;
        let test = gpu.compute_pipeline("hzb test", &test, &[sb; 6])?;
        let resolve = SurfaceResolve::new_listing_seen(
            gpu,
            compiler,
            &defines,
            "direct resolve (two lists, listing the blocks seen)",
        )?;
        let finish = gpu.compute_pipeline("cull finish", &finish, &[sb; 9])?;
        Ok(ComputeCullPipelines {
            extract_list,
            extract_new,
            raster,
            hzb,
            test,
            resolve,
            finish,
            max_groups_x: gpu.caps().max_compute_workgroup_count[0],
        })
    }
}

/// What culling did in the last frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ComputeCullStats {
    /// Blocks whose (min, max) holds the isovalue.
    pub blocks_occupied: u32,
    /// Blocks owning a pixel of the frame: next frame's pass A.
    pub blocks_visible: u32,
    /// Blocks drawn in pass A (those that owned a pixel last frame).
    pub blocks_drawn_first: u32,
    /// Blocks drawn in pass B (found possibly visible by the occlusion test).
    pub blocks_drawn_new: u32,
    /// Triangles extracted in pass A and pass B (more than a list's capacity: some were lost).
    pub triangles_first: u32,
    pub triangles_new: u32,
    /// Triangles pass B's cells would have made where their own occlusion test found them
    /// hidden, left out.
    pub triangles_new_hidden: u32,
}

impl ComputeCullStats {
    pub fn blocks_drawn(&self) -> u32 {
        self.blocks_drawn_first + self.blocks_drawn_new
    }

    pub fn triangles(&self) -> u32 {
        self.triangles_first + self.triangles_new
    }
}

/// Words of the culling statistics the test counts on the GPU: blocks occupied, listed for
/// pass B (`hzb_test.comp.glsl`).
const STATS_WORDS: u64 = 2;

/// Words of the frame's statistics on the host (`cull_finish.comp.glsl`).
const HOST_STATS_WORDS: u64 = 8;

/// Words of each extraction's statistics: triangles made, blocks classified, triangles of
/// cells left out as hidden (`extract.comp.glsl`).
const EXTRACT_STATS_WORDS: u64 = 3;

/// Per-volume, per-frame-size culling state carried from frame to frame: block flags and
/// lists, the pyramid, and pass B's triangle lists.
pub struct ComputeCullState {
    /// Per block, the number of the last frame it owned a pixel in ([`Self::seen_number`]; 0:
    /// none since the last reset).
    pub(super) flags: Buffer,
    /// Pass-A lists, used in turn: one is drawn while the other is rebuilt for next frame.
    pub(super) lists: [Buffer; 2],
    pub(super) new_blocks: Buffer,
    /// Blocks occupied, listed for pass B (`STATS_WORDS` words).
    pub(super) stats: Buffer,
    /// The extraction's (triangles, blocks classified, triangles left out as hidden) of pass A
    /// and pass B.
    pub(super) extract_stats: [Buffer; 2],
    pub(super) hzb: Buffer,
    /// Per block, the box of its cells that made triangles at the isovalue it was made at:
    /// tested in place of the block's box at that isovalue.
    pub cell_boxes: CellBoxes,
    /// The statistics of the last frame on the host, written by the finishing pass: `stats`,
    /// the blocks visible, pass A's list length, pass A's triangles, then pass B's
    /// `extract_stats`.
    pub(super) readback: Readback,
    /// Pass B's triangles.
    pub new_lists: TriangleLists,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) block_count: u32,
    pub(super) frame: Cell<usize>,
    /// The frame ([`crate::raster::RasterFrame::frame_stamp`]) of the last frame recorded with this state,
    /// whose finishing pass emptied what the next frame fills: its counts and lists, and its
    /// target's triangle counts. A next frame into the same target with no other frame begun
    /// in it between needs no fills before its first pass. `None` after a reset.
    pub(super) emptied_after: Cell<Option<(u64, u32)>>,
}

impl ComputeCullState {
    /// State for `prepared` drawn into frames like `target`; pass B's lists get the target's
    /// capacity (the first frame draws everything in view in pass B).
    pub fn new(
        gpu: &Gpu,
        prepared: &PreparedVolume,
        target: &ComputeTarget,
    ) -> Result<ComputeCullState> {
        let b = prepared.octree.level_dims[0];
        let blocks = b[0] * b[1] * b[2];
        let (w, h) = (target.frame.width, target.frame.height);
        let list = block_list::bytes(blocks as u64);
        let specs = [
            ("hzb cull block flags", 4 * blocks as u64),
            ("hzb cull first blocks A", list),
            ("hzb cull first blocks B", list),
            ("hzb cull new blocks", list),
            ("hzb cull stats", 4 * STATS_WORDS),
            ("hzb cull extract stats A", 4 * EXTRACT_STATS_WORDS),
            ("hzb cull extract stats B", 4 * EXTRACT_STATS_WORDS),
            ("hzb", hzb_bytes(w, h)),
        ];
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let mut made: Vec<Buffer> = Vec::new();
        for (name, bytes) in specs {
            made.push(gpu.create_buffer(name, bytes, usage, MemoryLocation::GpuOnly)?);
        }
        let new_lists = TriangleLists::new(gpu, target.lists.capacity)?;
        let Ok([flags, a, b, new_blocks, stats, es_a, es_b, hzb]) = <[Buffer; 8]>::try_from(made)
        else {
            unreachable!("eight buffers were made")
        };
        let state = ComputeCullState {
            flags,
            lists: [a, b],
            new_blocks,
            stats,
            extract_stats: [es_a, es_b],
            hzb,
            cell_boxes: CellBoxes::new(gpu, "hzb cull cell boxes", blocks as u64)?,
            readback: gpu.create_readback("hzb cull stats (host)", 4 * HOST_STATS_WORDS)?,
            new_lists,
            width: w,
            height: h,
            block_count: blocks,
            frame: Cell::new(0),
            emptied_after: Cell::new(None),
        };
        state.reset(gpu)?;
        Ok(state)
    }

    /// Forgets what earlier frames saw (a cut in the camera path, a new volume): the next frame
    /// draws nothing in pass A.
    pub fn reset(&self, gpu: &Gpu) -> Result<()> {
        self.emptied_after.set(None);
        gpu.submit("reset compute culling", |rec| {
            for b in [
                &self.flags,
                &self.lists[0],
                &self.lists[1],
                &self.new_blocks,
            ] {
                rec.fill_buffer(b, 0);
            }
            self.cell_boxes.record_clear(rec);
            for b in [&self.stats, &self.extract_stats[0], &self.extract_stats[1]] {
                rec.fill_buffer(b, 0);
            }
        })?;
        Ok(())
    }

    /// The number the recorded frame gives the blocks that own its pixels: 2 and up, so that
    /// the flags a reset leaves (0) and the number before the first frame (1) match none.
    pub(super) fn seen_number(&self) -> u32 {
        Self::number_of(self.frame.get())
    }

    /// The flag of the blocks the recorded frame's pass A draws: the frame before's number.
    pub(super) fn first_pass_number(&self) -> u32 {
        match self.frame.get() {
            0 => 1,
            frame => Self::number_of(frame - 1),
        }
    }

    fn number_of(frame: usize) -> u32 {
        (frame % (u32::MAX as usize - 2)) as u32 + 2
    }

    pub(super) fn first(&self) -> &Buffer {
        &self.lists[self.frame.get() % 2]
    }

    pub(super) fn next(&self) -> &Buffer {
        &self.lists[(self.frame.get() + 1) % 2]
    }

    /// What the last recorded frame did (read after it was submitted): written to the host at
    /// the frame's end, so reading takes no submission.
    pub fn read_stats(&self) -> ComputeCullStats {
        let mut s = [0u32; 8];
        if let Some(bytes) = self.readback.bytes().get(..32) {
            s = bytemuck::pod_read_unaligned(bytes);
        }
        ComputeCullStats {
            blocks_occupied: s[0],
            blocks_drawn_new: s[1],
            blocks_visible: s[2],
            blocks_drawn_first: s[3],
            triangles_first: s[4],
            triangles_new: s[5],
            triangles_new_hidden: s[7],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ComputeCullState;

    /// Frame numbers never match the flags a reset leaves (0) or the number before the first
    /// frame (1), and two frames in a row differ, also where the numbers wrap around.
    #[test]
    fn frame_numbers_skip_the_reset_flags_and_differ_frame_to_frame() {
        let wrap = u32::MAX as usize - 2;
        for frame in [0, 1, 2, 1000, wrap - 2, wrap - 1, wrap, wrap + 1] {
            let (now, before) = (
                ComputeCullState::number_of(frame),
                ComputeCullState::number_of(frame.wrapping_sub(1)),
            );
            assert!(now >= 2, "frame {frame}: {now}");
            if frame > 0 {
                assert_ne!(now, before, "frame {frame}");
            }
        }
        assert_eq!(ComputeCullState::number_of(0), 2);
        assert_eq!(ComputeCullState::number_of(wrap), 2);
    }
}
