//! Per block, the box of its cells that made triangles at an isovalue, as the last extraction
//! of the block recorded it (`cell_box.glsl`, `cell_box_record.glsl`). Both paths' occlusion
//! culling test it in place of the block's whole box: every triangle the block makes at that
//! isovalue lies in it, and on a surface it is often a thin slab of the block.

use crate::error::Result;
use crate::iso::PreparedVolume;
use std::cell::Cell;
use tessera_data::minmax::BLOCK_CELLS;
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation, Recorder};

/// Bits per coordinate of a packed box: six coordinates and a valid bit in 32 bits, for blocks
/// up to 32 cells a side.
pub const CELL_BOX_BITS: u32 = 5;
const _: () = assert!(
    BLOCK_CELLS[0] <= 1 << CELL_BOX_BITS
        && BLOCK_CELLS[1] <= 1 << CELL_BOX_BITS
        && BLOCK_CELLS[2] <= 1 << CELL_BOX_BITS
);

/// The bit of a packed box that says it holds one (a block without triangles has none).
pub const CELL_BOX_VALID: u32 = 1 << 31;

/// A block's cells that made triangles at an isovalue: the first and last, local to the block.
pub type CellBox = [[u32; 3]; 2];

/// The defines `cell_box.glsl` needs.
pub(crate) fn cell_box_defines() -> [(String, String); 2] {
    [
        ("CELL_BOX_BITS".into(), format!("{CELL_BOX_BITS}u")),
        ("CELL_BOX_VALID".into(), format!("{CELL_BOX_VALID}u")),
    ]
}

/// The boxes of one volume's blocks: two words per block, the packed box and the bits of the
/// isovalue it was recorded at. Forgotten when the state meets another [`PreparedVolume`] or
/// is reset; samples rewritten in place in the same prepared volume need a reset.
pub struct CellBoxes {
    pub(super) buffer: Buffer,
    /// [`PreparedVolume::id`] of the volume the boxes were made from (0: none yet).
    volume: Cell<u64>,
}

impl CellBoxes {
    pub fn new(gpu: &Gpu, name: &str, blocks: u64) -> Result<CellBoxes> {
        let buffer = gpu.create_buffer(
            name,
            8 * blocks,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        Ok(CellBoxes {
            buffer,
            volume: Cell::new(0),
        })
    }

    /// Records forgetting every box (before a barrier).
    pub(super) fn record_clear(&self, rec: &Recorder) {
        rec.fill_buffer(&self.buffer, 0);
    }

    /// Records forgetting the boxes when they were made from another volume than `prepared`
    /// (the same block grid says nothing about another volume's surface); before a barrier.
    /// Returns whether it recorded that.
    pub(super) fn record_keep_for(&self, rec: &Recorder, prepared: &PreparedVolume) -> bool {
        let forget = self.volume.replace(prepared.id()) != prepared.id();
        if forget {
            self.record_clear(rec);
        }
        forget
    }

    /// Per block, the box recorded at `iso` (`None` for blocks not extracted at `iso` since
    /// the boxes were last cleared, or without triangles).
    pub fn read(&self, gpu: &Gpu, iso: f32) -> Result<Vec<Option<CellBox>>> {
        let mask = (1 << CELL_BOX_BITS) - 1;
        let boxes: Vec<[u32; 2]> = gpu.read_buffer_as(&self.buffer)?;
        Ok(boxes
            .iter()
            .map(|&[packed, iso_bits]| {
                let valid = packed & CELL_BOX_VALID != 0 && iso_bits == iso.to_bits();
                let at = |k: u32| (packed >> (k * CELL_BOX_BITS)) & mask;
                valid.then(|| [[at(0), at(1), at(2)], [at(3), at(4), at(5)]])
            })
            .collect())
    }
}
