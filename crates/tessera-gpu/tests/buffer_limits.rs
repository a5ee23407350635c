//! Buffers are bound whole, so a storage buffer larger than the device's largest storage buffer
//! range could never be bound within it: it is refused when made, naming the buffer and the
//! limit.

mod common;
use common::{assert_clean, open};
use tessera_gpu::{vk, MemoryLocation};

#[test]
fn a_storage_buffer_past_the_range_is_refused_by_name() {
    let Some(gpu) = open() else {
        return;
    };
    let range = gpu.caps().max_storage_buffer_range;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let message = gpu
        .create_buffer("too wide", range + 4, storage, MemoryLocation::GpuOnly)
        .err()
        .expect("a storage buffer past the range")
        .to_string();
    assert!(
        message.contains("too wide")
            && message.contains(&range.to_string())
            && message.contains("largest storage buffer"),
        "{message}"
    );
    // Making the buffers that may be made allocates them: only where the range is small.
    if range <= 1 << 30 {
        gpu.create_buffer("widest", range, storage, MemoryLocation::GpuOnly)
            .expect("a storage buffer of the whole range");
        let copy_only = vk::BufferUsageFlags::TRANSFER_DST;
        gpu.create_buffer("not bound", range + 4, copy_only, MemoryLocation::GpuOnly)
            .expect("a buffer never bound has no range to keep");
    }
    assert_clean(&gpu);
}
