//! Raster occlusion culling for `direct` (paper D, §3.5): regions of 8×8×8 cells whose
//! proxy quad is hidden behind the geometry drawn from last frame's visible set are not
//! extracted at all.
//!
//! A frame: list the occupied regions; draw last frame's visible blocks (the likely
//! occluders); draw one quad per occupied region at its nearest depth, depth-tested without
//! writing, flagging the regions with a surviving fragment; compact the flags into this
//! frame's newly visible blocks (drawn next) and next frame's occluder list. A region's quad
//! covers its blocks' cell boxes ([`super::cell_boxes`]) where the task shader recorded them
//! at this isovalue, else the blocks whole.

use crate::builtin_shader;
use crate::config::common_defines;
use crate::error::Result;
use crate::iso::direct::cell_boxes::{cell_box_defines, CellBoxes};
use crate::iso::direct::{block_list, DirectParams, COLOR_FORMAT, DEPTH_FORMAT};
use crate::iso::PreparedVolume;
use std::cell::Cell;
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, RenderTargets, ShaderCompiler,
    Slot,
};

/// Modes of `cull_setup.comp.glsl`: empty the frame's lists; the occupied-region count to the
/// quad draw's workgroups; the block counts to the task draws' workgroups.
const SETUP_CLEAR: u32 = 0;
const SETUP_QUADS: u32 = 1;
const SETUP_BLOCK_DRAWS: u32 = 2;

/// Cells per region along each axis: two blocks stacked in z.
pub const REGION_CELLS: [u32; 3] = [8, 8, 8];

pub fn region_dims(volume_dims: [u32; 3]) -> [u32; 3] {
    [0, 1, 2].map(|a| (volume_dims[a] - 1).div_ceil(REGION_CELLS[a]))
}

/// The culling pipelines, shared by every volume.
pub struct CullPipelines {
    max_groups_x: u32,
    setup: Pipeline,
    occupied: Pipeline,
    quads: Pipeline,
    compact: Pipeline,
}

impl CullPipelines {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<CullPipelines> {
        let mut defines = common_defines();
        defines.extend(cell_box_defines());
        let compile = |s| compiler.compile(&s, &defines);
        let setup = compile(builtin_shader!("cull_setup.comp.glsl"))?;
        let occupied = compile(builtin_shader!("cull_occupied.comp.glsl"))?;
        let mesh = compile(builtin_shader!("cull_quads.mesh.glsl"))?;
        let frag = compile(builtin_shader!("cull_quads.frag.glsl"))?;
        let compact = compile(builtin_shader!("cull_compact.comp.glsl"))?;
        let sb = Slot::StorageBuffer;
        let quad_targets = RenderTargets {
            depth_write: false,
            color_write: false,
            representative_fragments: true,
            ..RenderTargets::color_depth(COLOR_FORMAT, DEPTH_FORMAT)
        };
        Ok(CullPipelines {
            max_groups_x: gpu.caps().max_compute_workgroup_count[0],
            setup: gpu.compute_pipeline("cull setup", &setup, &[sb, sb, sb])?,
            occupied: gpu.compute_pipeline("cull occupied regions", &occupied, &[sb, sb, sb])?,
            quads: gpu.graphics_pipeline_for(
                "cull proxy quads",
                &[&mesh, &frag],
                &[sb; 4],
                &quad_targets,
            )?,
            compact: gpu.compute_pipeline("cull compact", &compact, &[sb, sb, sb, sb])?,
        })
    }
}

/// What culling found in the last frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CullStats {
    pub regions_occupied: u32,
    /// Blocks of regions found visible (next frame's occluders).
    pub blocks_visible: u32,
    /// Blocks drawn as occluders from the previous frame.
    pub blocks_drawn_first: u32,
    /// Blocks drawn after the visibility test (visible now, not drawn first).
    pub blocks_drawn_new: u32,
}

/// Per-volume culling state that carries visibility from one frame to the next.
pub struct CullState {
    occupied: Buffer,
    visible: Buffer,
    previous: Buffer,
    /// Occluder lists, used in turn: one is drawn this frame while the other is rebuilt.
    lists: [Buffer; 2],
    new_blocks: Buffer,
    /// Per block, the cells that made triangles at the isovalue of its last extraction.
    pub cell_boxes: CellBoxes,
    frame: Cell<usize>,
}

/// One word per region.
fn flag_buffer(gpu: &Gpu, name: &str, regions: u64) -> Result<Buffer> {
    Ok(gpu.create_buffer(
        name,
        4 * regions,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?)
}

impl CullState {
    pub fn new(gpu: &Gpu, prepared: &PreparedVolume) -> Result<CullState> {
        let r = region_dims(prepared.volume.dims);
        let regions = (r[0] * r[1] * r[2]) as u64;
        let b = prepared.octree.level_dims[0];
        let blocks = (b[0] * b[1] * b[2]) as u64;
        let state = CullState {
            occupied: block_list::create(gpu, "cull occupied regions", regions)?,
            visible: flag_buffer(gpu, "cull visible flags", regions)?,
            previous: flag_buffer(gpu, "cull previous flags", regions)?,
            lists: [
                block_list::create(gpu, "cull occluder blocks A", blocks)?,
                block_list::create(gpu, "cull occluder blocks B", blocks)?,
            ],
            new_blocks: block_list::create(gpu, "cull new blocks", blocks)?,
            cell_boxes: CellBoxes::new(gpu, "cull cell boxes", blocks)?,
            frame: Cell::new(0),
        };
        state.reset(gpu)?;
        Ok(state)
    }

    /// Forgets what earlier frames saw (a cut in the camera path, a new volume).
    pub fn reset(&self, gpu: &Gpu) -> Result<()> {
        gpu.submit("reset culling", |rec| {
            for b in [&self.previous, &self.lists[0], &self.lists[1]] {
                rec.fill_buffer(b, 0);
            }
            self.cell_boxes.record_clear(rec);
        })?;
        Ok(())
    }

    fn drawn_first(&self) -> &Buffer {
        &self.lists[self.frame.get() % 2]
    }

    fn rebuilt(&self) -> &Buffer {
        &self.lists[(self.frame.get() + 1) % 2]
    }

    pub fn read_stats(&self, gpu: &Gpu) -> Result<CullStats> {
        let count = |b: &Buffer| -> Result<u32> { Ok(block_list::count(&gpu.read_buffer(b)?)) };
        // After a frame the lists have turned over: the one drawn first is now `rebuilt()`.
        Ok(CullStats {
            regions_occupied: count(&self.occupied)?,
            blocks_visible: count(self.drawn_first())?,
            blocks_drawn_first: count(self.rebuilt())?,
            blocks_drawn_new: count(&self.new_blocks)?,
        })
    }
}

/// How a culled frame draws the isosurface of a block list; given by `Direct`.
pub trait DrawBlockList {
    fn draw_blocks(&self, rec: &Recorder, list: &Buffer) -> Result<()>;
}

impl CullPipelines {
    /// Records a culled frame. Rendering into `color`/`depth` (in GENERAL layout) happens in two
    /// passes around the visibility compaction; the first one clears.
    #[allow(clippy::too_many_arguments)]
    pub fn record_frame(
        &self,
        rec: &Recorder,
        state: &CullState,
        prepared: &PreparedVolume,
        params: &DirectParams,
        color: &tessera_gpu::Image,
        depth: &tessera_gpu::Image,
        clear: [f32; 4],
        draw: &dyn DrawBlockList,
    ) -> Result<()> {
        let push = bytemuck::bytes_of(params);
        let next = state.rebuilt();
        let setup = |mode: u32| {
            rec.dispatch_groups(
                &self.setup,
                &[
                    Binding::Buffer(&state.occupied),
                    Binding::Buffer(&state.new_blocks),
                    Binding::Buffer(next),
                ],
                &mode.to_le_bytes(),
                [1, 1, 1],
            );
            rec.barrier();
        };
        state.cell_boxes.record_keep_for(rec, prepared);
        setup(SETUP_CLEAR);
        let r = region_dims(prepared.volume.dims);
        rec.dispatch_groups(
            &self.occupied,
            &[
                Binding::Buffer(&prepared.octree.nodes),
                Binding::Buffer(&state.occupied),
                Binding::Buffer(&state.visible),
            ],
            push,
            tessera_gpu::spread_groups((r[0] * r[1] * r[2]).div_ceil(64), self.max_groups_x),
        );
        rec.barrier();
        setup(SETUP_QUADS);
        rec.begin_rendering_ops(color, Some(depth), Some(clear));
        draw.draw_blocks(rec, state.drawn_first())?;
        rec.draw_mesh_tasks_indirect(
            &self.quads,
            &[
                Binding::Buffer(&state.occupied),
                Binding::Buffer(&state.visible),
                Binding::Buffer(&prepared.octree.nodes),
                Binding::Buffer(&state.cell_boxes.buffer),
            ],
            push,
            &state.occupied,
            block_list::ARGS_OFFSET,
        )?;
        rec.end_rendering();
        rec.barrier();
        rec.dispatch_groups(
            &self.compact,
            &[
                Binding::Buffer(&state.visible),
                Binding::Buffer(&state.previous),
                Binding::Buffer(&state.new_blocks),
                Binding::Buffer(next),
            ],
            push,
            tessera_gpu::spread_groups((r[0] * r[1] * r[2]).div_ceil(64), self.max_groups_x),
        );
        rec.barrier();
        setup(SETUP_BLOCK_DRAWS);
        rec.begin_rendering_ops(color, Some(depth), None);
        draw.draw_blocks(rec, &state.new_blocks)?;
        rec.end_rendering();
        rec.barrier();
        state.frame.set(state.frame.get() + 1);
        Ok(())
    }
}
