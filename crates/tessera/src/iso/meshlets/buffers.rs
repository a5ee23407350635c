//! The meshlet buffers on the GPU (`buffers.glsl`; content and order as
//! `tessera_data::meshlets::gpu_layout` fixes them), sized by capacities that grow when an
//! extraction overflows, and their readback as a [`MeshletMesh`].

use crate::error::{Error, Result};
use crate::iso::direct::block_list;
use bytemuck::{Pod, Zeroable};
use std::mem::size_of;
use tessera_data::meshlets::{Meshlet, MeshletMesh};
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation};

/// The totals of an extraction, as `buffers.glsl` declares them: meshlets, vertices and
/// triangles reserved (each meshlet's triangles rounded up to a multiple of 4), and the
/// overflow bits.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct MeshletCounters {
    pub meshlets: u32,
    pub vertices: u32,
    pub triangles: u32,
    pub overflow: u32,
}

impl MeshletCounters {
    /// Bytes of the surface these totals describe: descriptors, f32 positions and normals,
    /// 8-bit local indices (the paper's memory footprint).
    pub fn stored_bytes(&self) -> u64 {
        u64::from(self.meshlets) * size_of::<Meshlet>() as u64
            + u64::from(self.vertices) * 24
            + u64::from(self.triangles) * 3
    }
}

/// A block's reservation passed a capacity (`MESHLET_OVERFLOW_CAPACITY`).
pub const OVERFLOW_CAPACITY: u32 = 1;
/// An extraction counted otherwise than its region analysis (`MESHLET_OVERFLOW_MISMATCH`).
pub const OVERFLOW_MISMATCH: u32 = 2;

/// How many meshlets, vertices and triangles the output buffers hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshletCapacity {
    pub meshlets: u32,
    pub vertices: u32,
    /// A multiple of 4, as reservations are.
    pub triangles: u32,
}

impl MeshletCapacity {
    /// `triangles` rounded up to the reservations' multiple of 4; every count at least what
    /// one meshlet needs, so no buffer is empty.
    pub fn new(meshlets: u32, vertices: u32, triangles: u32) -> MeshletCapacity {
        MeshletCapacity {
            meshlets: meshlets.max(1),
            vertices: vertices.max(1),
            triangles: triangles.max(1).saturating_add(3) & !3,
        }
    }

    /// Room for `counters`' totals with a quarter of headroom (the rule every growing buffer
    /// of the crate follows), never less than now.
    fn grown_to(self, counters: &MeshletCounters) -> MeshletCapacity {
        let grow = crate::capacity::grown_capacity;
        MeshletCapacity::new(
            grow(self.meshlets, counters.meshlets),
            grow(self.vertices, counters.vertices),
            grow(self.triangles, counters.triangles),
        )
    }

    fn holds(&self, counters: &MeshletCounters) -> bool {
        counters.meshlets <= self.meshlets
            && counters.vertices <= self.vertices
            && counters.triangles <= self.triangles
    }
}

impl Default for MeshletCapacity {
    /// Enough for a surface through some thousand blocks; larger ones grow.
    fn default() -> Self {
        MeshletCapacity::new(4 << 10, 256 << 10, 512 << 10)
    }
}

/// An extraction's result on the GPU, for rendering or readback: the output buffers, the
/// occupied-block list they were made from, and the totals of the last extraction.
pub struct GpuMeshlets {
    /// Occupied blocks (`block_list.glsl` layout), one entry per block whose range holds
    /// the isovalue.
    pub blocks: Buffer,
    /// Entries of `blocks` whose block does not fit one meshlet whole (`block_list.glsl`
    /// layout): the compute path's second pass partitions them.
    pub split_blocks: Buffer,
    pub counters: Buffer,
    pub meshlets: Buffer,
    pub positions: Buffer,
    pub normals: Buffer,
    pub local_indices: Buffer,
    /// Per occupied-block entry: first meshlet, meshlet count.
    pub block_meshlets: Buffer,
    pub capacity: MeshletCapacity,
    /// Entries the block list and `block_meshlets` hold.
    pub block_capacity: u32,
    /// Totals of the last extraction; all within `capacity` once it returned.
    pub totals: MeshletCounters,
}

const OUTPUT_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw(),
);

impl GpuMeshlets {
    /// Buffers for a volume of `block_count` blocks and outputs of `capacity`.
    pub fn new(gpu: &Gpu, block_count: u32, capacity: MeshletCapacity) -> Result<GpuMeshlets> {
        let block_capacity = block_count.max(1);
        let output = |name: &str, bytes: u64| {
            gpu.create_buffer(name, bytes, OUTPUT_USAGE, MemoryLocation::GpuOnly)
        };
        let (m, v, t) = (
            u64::from(capacity.meshlets),
            u64::from(capacity.vertices),
            u64::from(capacity.triangles),
        );
        Ok(GpuMeshlets {
            blocks: block_list::create(gpu, "meshlet occupied blocks", block_capacity.into())?,
            split_blocks: block_list::create(gpu, "meshlet split blocks", block_capacity.into())?,
            counters: output("meshlet counters", size_of::<MeshletCounters>() as u64)?,
            meshlets: output("meshlets", m * size_of::<Meshlet>() as u64)?,
            positions: output("meshlet positions", v * 12)?,
            normals: output("meshlet normals", v * 12)?,
            local_indices: output("meshlet local indices", t * 3)?,
            block_meshlets: output("block meshlets", u64::from(block_capacity) * 8)?,
            capacity,
            block_capacity,
            totals: MeshletCounters::default(),
        })
    }

    /// `mesh` uploaded in the layout an extraction writes (no block list), to be drawn like
    /// extracted meshlets: the offline reference's meshlets, or meshlets read from a file.
    pub fn upload(gpu: &Gpu, mesh: &MeshletMesh) -> Result<GpuMeshlets> {
        mesh.validate_structure()?;
        let too_many = || Error::Invalid("more than 2^32 meshlets, vertices or triangles".into());
        let count = |n: usize| u32::try_from(n).map_err(|_| too_many());
        let totals = MeshletCounters {
            meshlets: count(mesh.meshlets.len())?,
            vertices: count(mesh.positions.len())?,
            triangles: count(mesh.triangle_count())?,
            overflow: 0,
        };
        let capacity = MeshletCapacity::new(totals.meshlets, totals.vertices, totals.triangles);
        let mut out = GpuMeshlets::new(gpu, 1, capacity)?;
        let mut indices = mesh.local_indices.clone();
        indices.resize(indices.len().next_multiple_of(4), 0);
        for (buffer, bytes) in [
            (&out.counters, bytemuck::bytes_of(&totals)),
            (&out.meshlets, bytemuck::cast_slice(&mesh.meshlets)),
            (&out.positions, bytemuck::cast_slice(&mesh.positions)),
            (&out.normals, bytemuck::cast_slice(&mesh.normals)),
            (&out.local_indices, &indices[..]),
        ] {
            if !bytes.is_empty() {
                gpu.write_buffer(buffer, bytes)?;
            }
        }
        out.totals = totals;
        Ok(out)
    }

    /// Replaces the output buffers by larger ones when `counters` did not fit; whether it did.
    pub(crate) fn grow_for(&mut self, gpu: &Gpu, counters: &MeshletCounters) -> Result<bool> {
        if self.capacity.holds(counters) {
            return Ok(false);
        }
        *self = GpuMeshlets::new(gpu, self.block_capacity, self.capacity.grown_to(counters))?;
        Ok(true)
    }

    /// Reads the last extraction back: the meshlets as the GPU wrote them (blocks in any
    /// order, up to 3 unused triangles after each meshlet's), each compared after
    /// [`MeshletMesh::in_origin_order`].
    pub fn read(&self, gpu: &Gpu) -> Result<MeshletMesh> {
        let t = self.totals;
        let vertices = t.vertices as usize;
        Ok(MeshletMesh {
            positions: gpu.read_elements(&self.positions, vertices)?,
            normals: gpu.read_elements(&self.normals, vertices)?,
            local_indices: gpu.read_elements(&self.local_indices, t.triangles as usize * 3)?,
            meshlets: gpu.read_elements(&self.meshlets, t.meshlets as usize)?,
        })
    }

    /// The occupied-block entries and their `(first meshlet, meshlet count)`, read back.
    pub fn read_block_meshlets(&self, gpu: &Gpu) -> Result<Vec<(u32, [u32; 2])>> {
        let bytes = gpu.read_buffer(&self.blocks)?;
        let count = (block_list::count(&bytes) as usize).min(self.block_capacity as usize);
        let list: Vec<u32> = bytemuck::allocation::pod_collect_to_vec(&bytes);
        let header = size_of::<block_list::BlockListHeader>() / 4;
        let ranges: Vec<[u32; 2]> = gpu.read_buffer_as(&self.block_meshlets)?;
        Ok((0..count).map(|i| (list[header + i], ranges[i])).collect())
    }
}
