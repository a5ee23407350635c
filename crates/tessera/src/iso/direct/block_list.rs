//! Lists of block or region ids on the GPU (`block_list.glsl`): a header with the entry count
//! and the indirect arguments of one workgroup per entry, then the ids. The culling passes of
//! both paths share this one layout, and so do the extractions that run one workgroup per
//! occupied block (`iso::meshlets`, `iso::pmb`), which also share the pass that turns the
//! count into the arguments (`block_args.comp.glsl`).

use crate::builtin_shader;
use crate::error::Result;
use bytemuck::{Pod, Zeroable};
use std::mem::{offset_of, size_of};
use tessera_gpu::{
    vk, Binding, Buffer, Gpu, MemoryLocation, Pipeline, Recorder, ShaderCompiler, Slot,
};

/// The header of a list, as `block_list.glsl` declares it.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct BlockListHeader {
    pub count: u32,
    pub args: [u32; 3],
}

impl BlockListHeader {
    /// An empty list: no entries, no workgroups.
    pub const EMPTY: BlockListHeader = BlockListHeader {
        count: 0,
        args: [0, 1, 1],
    };
}

/// Byte offset of the indirect arguments in a list buffer.
pub const ARGS_OFFSET: u64 = offset_of!(BlockListHeader, args) as u64;
/// Byte offset of the entry count.
pub const COUNT_OFFSET: u64 = offset_of!(BlockListHeader, count) as u64;

/// A list buffer with room for `entries` ids, usable for indirect draws and dispatches.
pub fn create(gpu: &Gpu, name: &str, entries: u64) -> Result<Buffer> {
    Ok(gpu.create_buffer(
        name,
        bytes(entries),
        vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?)
}

/// The entry count of a list read back from the GPU.
pub fn count(bytes: &[u8]) -> u32 {
    let at = COUNT_OFFSET as usize;
    bytemuck::pod_read_unaligned(&bytes[at..at + 4])
}

/// Bytes of a list of `entries` ids.
pub fn bytes(entries: u64) -> u64 {
    size_of::<BlockListHeader>() as u64 + 4 * entries
}

/// The pass that turns a list's count into the indirect arguments of one workgroup per entry
/// (`block_args.comp.glsl`).
pub fn args_pipeline(gpu: &Gpu, compiler: &ShaderCompiler, name: &str) -> Result<Pipeline> {
    let shader = compiler.compile(&builtin_shader!("block_args.comp.glsl"), &[])?;
    Ok(gpu.compute_pipeline(name, &shader, &[Slot::StorageBuffer])?)
}

/// Records [`args_pipeline`]'s pass over `list`, once its count is final.
pub fn record_args(rec: &Recorder, pipeline: &Pipeline, list: &Buffer) {
    rec.dispatch_groups(pipeline, &[Binding::Buffer(list)], &[], [1, 1, 1]);
}

/// The passes that fill `list` with the occupied blocks of an extraction: the list emptied,
/// `occupied` run over `block_count` blocks (bound to the octree `nodes` and the list, with
/// the extraction's `push` constants, so it tests the same isovalue), then [`record_args`].
/// Ends with a barrier, so the extraction may dispatch indirectly from the list.
#[allow(clippy::too_many_arguments)]
pub fn record_occupied(
    rec: &Recorder,
    occupied: &Pipeline,
    args: &Pipeline,
    nodes: &Buffer,
    list: &Buffer,
    push: &[u8],
    block_count: u32,
    max_groups_x: u32,
) {
    rec.update_buffer(list, bytemuck::bytes_of(&BlockListHeader::EMPTY));
    rec.barrier();
    let groups = block_count.div_ceil(occupied.local_size[0]);
    rec.dispatch_groups(
        occupied,
        &[Binding::Buffer(nodes), Binding::Buffer(list)],
        push,
        tessera_gpu::spread_groups(groups, max_groups_x),
    );
    rec.barrier();
    record_args(rec, args, list);
    rec.barrier();
}
