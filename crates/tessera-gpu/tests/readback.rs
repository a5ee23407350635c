//! Reading a buffer back as typed elements: the first elements only, the whole buffer, and a
//! request past the buffer's end refused with its name.

mod common;
use common::{assert_clean, open};
use tessera_gpu::{vk, MemoryLocation};

#[test]
fn a_buffer_reads_back_as_elements() {
    let Some(gpu) = open() else {
        return;
    };
    let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
    let words: Vec<u32> = (0..64u32).map(|i| i * 7 + 1).collect();
    let buffer = gpu
        .create_buffer("numbered words", 256, usage, MemoryLocation::GpuOnly)
        .unwrap();
    gpu.write_buffer(&buffer, bytemuck::cast_slice(&words))
        .unwrap();

    let all: Vec<u32> = gpu.read_buffer_as(&buffer).unwrap();
    assert_eq!(all, words);
    let first: Vec<u32> = gpu.read_elements(&buffer, 5).unwrap();
    assert_eq!(first, words[..5]);
    // Larger elements: 12-byte triples, the trailing 4 bytes of the buffer left out.
    let triples: Vec<[u32; 3]> = gpu.read_buffer_as(&buffer).unwrap();
    assert_eq!(triples.len(), 21);
    assert_eq!(triples[20], [words[60], words[61], words[62]]);
    let none: Vec<u32> = gpu.read_elements(&buffer, 0).unwrap();
    assert!(none.is_empty());

    let past = gpu
        .read_elements::<u32>(&buffer, 65)
        .unwrap_err()
        .to_string();
    assert!(
        past.contains("numbered words") && past.contains("65 elements"),
        "{past}"
    );
    let huge = gpu.read_elements::<[f32; 3]>(&buffer, usize::MAX);
    assert!(huge.is_err());
    assert_clean(&gpu);
}
