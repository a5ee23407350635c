//! The PMB output on the GPU (`extract.comp.glsl` declares it): the occupied-block list, the
//! totals, a descriptor per block with triangles, and the vertex and index arrays, sized by
//! capacities that grow when an extraction overflows; and its readback as a [`PmbMesh`].

use crate::error::Result;
use crate::iso::direct::block_list;
use bytemuck::{Pod, Zeroable};
use std::mem::size_of;
use tessera_data::pmb::{PmbBlock, PmbMesh};
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation};

/// The totals of an extraction, as `extract.comp.glsl` declares them: blocks written,
/// vertices and triangles reserved (counting on past the capacities), and whether a block's
/// reservation did not fit (nonzero).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PmbCounters {
    pub blocks: u32,
    pub vertices: u32,
    pub triangles: u32,
    pub overflow: u32,
}

impl PmbCounters {
    /// Bytes of the surface these totals describe: block descriptors, f32 positions and
    /// normals, 16-bit indices (paper C's memory footprint of PMB).
    pub fn stored_bytes(&self) -> u64 {
        u64::from(self.blocks) * std::mem::size_of::<tessera_data::pmb::PmbBlock>() as u64
            + u64::from(self.vertices) * 24
            + u64::from(self.triangles) * 6
    }
}

/// How many vertices and triangles the output buffers hold. Descriptors need no capacity:
/// there is room for one per block of the volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PmbCapacity {
    pub vertices: u32,
    pub triangles: u32,
}

impl PmbCapacity {
    /// At least one of each, so no buffer is empty.
    pub fn new(vertices: u32, triangles: u32) -> PmbCapacity {
        PmbCapacity {
            vertices: vertices.max(1),
            triangles: triangles.max(1),
        }
    }

    /// Room for `counters`' totals with a quarter of headroom (the rule every growing buffer
    /// of the crate follows), never less than now.
    fn grown_to(self, counters: &PmbCounters) -> PmbCapacity {
        let grow = crate::capacity::grown_capacity;
        PmbCapacity::new(
            grow(self.vertices, counters.vertices),
            grow(self.triangles, counters.triangles),
        )
    }

    fn holds(&self, counters: &PmbCounters) -> bool {
        counters.vertices <= self.vertices && counters.triangles <= self.triangles
    }
}

impl Default for PmbCapacity {
    /// Enough for a surface through some thousand blocks; larger ones grow.
    fn default() -> Self {
        PmbCapacity::new(256 << 10, 512 << 10)
    }
}

/// An extraction's result on the GPU, for rendering or readback.
pub struct GpuPmb {
    /// Occupied blocks (`block_list.glsl` layout): PMB block ids whose range holds the
    /// isovalue.
    pub blocks: Buffer,
    pub counters: Buffer,
    /// One [`PmbBlock`] per block with triangles, in any order.
    pub descriptors: Buffer,
    pub positions: Buffer,
    pub normals: Buffer,
    /// 16-bit indices, three per triangle, local to their block.
    pub indices: Buffer,
    pub capacity: PmbCapacity,
    /// PMB blocks of the volume: entries of the block list and descriptors.
    pub block_capacity: u32,
    /// Cells per block along x, y and z.
    pub block_size: [u32; 3],
    /// Totals of the last extraction; all within `capacity` once it returned.
    pub totals: PmbCounters,
}

const OUTPUT_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw(),
);

impl GpuPmb {
    /// Buffers for a volume of `block_count` blocks of `block_size` cells and outputs of
    /// `capacity`.
    pub fn new(
        gpu: &Gpu,
        block_size: [u32; 3],
        block_count: u32,
        capacity: PmbCapacity,
    ) -> Result<GpuPmb> {
        let block_capacity = block_count.max(1);
        let output = |name: &str, bytes: u64| {
            gpu.create_buffer(name, bytes, OUTPUT_USAGE, MemoryLocation::GpuOnly)
        };
        let (v, t) = (u64::from(capacity.vertices), u64::from(capacity.triangles));
        // Index bytes rounded up to whole words: fills and copies work in words.
        let index_bytes = (t * 3 * 2).next_multiple_of(4);
        Ok(GpuPmb {
            blocks: block_list::create(gpu, "PMB occupied blocks", block_capacity.into())?,
            counters: output("PMB counters", size_of::<PmbCounters>() as u64)?,
            descriptors: output(
                "PMB blocks",
                u64::from(block_capacity) * size_of::<PmbBlock>() as u64,
            )?,
            positions: output("PMB positions", v * 12)?,
            normals: output("PMB normals", v * 12)?,
            // Also the graphics draw's index buffer.
            indices: gpu.create_buffer(
                "PMB indices",
                index_bytes,
                OUTPUT_USAGE | vk::BufferUsageFlags::INDEX_BUFFER,
                MemoryLocation::GpuOnly,
            )?,
            capacity,
            block_capacity,
            block_size,
            totals: PmbCounters::default(),
        })
    }

    /// Replaces the output buffers by larger ones when `counters` did not fit; whether it did.
    pub(crate) fn grow_for(&mut self, gpu: &Gpu, counters: &PmbCounters) -> Result<bool> {
        if self.capacity.holds(counters) {
            return Ok(false);
        }
        *self = GpuPmb::new(
            gpu,
            self.block_size,
            self.block_capacity,
            self.capacity.grown_to(counters),
        )?;
        Ok(true)
    }

    /// Reads the last extraction back (blocks in the GPU's order).
    pub fn read(&self, gpu: &Gpu) -> Result<PmbMesh> {
        let t = self.totals;
        let vertices = t.vertices as usize;
        Ok(PmbMesh {
            block_size: self.block_size,
            positions: gpu.read_elements(&self.positions, vertices)?,
            normals: gpu.read_elements(&self.normals, vertices)?,
            indices: gpu.read_elements(&self.indices, t.triangles as usize * 3)?,
            blocks: gpu.read_elements(&self.descriptors, t.blocks as usize)?,
        })
    }

    /// The occupied-block list (PMB block ids), read back.
    pub fn read_occupied(&self, gpu: &Gpu) -> Result<Vec<u32>> {
        let bytes = gpu.read_buffer(&self.blocks)?;
        let count = (block_list::count(&bytes) as usize).min(self.block_capacity as usize);
        let list: Vec<u32> = bytemuck::allocation::pod_collect_to_vec(&bytes);
        let header = size_of::<block_list::BlockListHeader>() / 4;
        Ok(list[header..header + count].to_vec())
    }
}
