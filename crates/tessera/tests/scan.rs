//! The GPU's exclusive prefix sum (`tessera::scan`) against the CPU's, for counts below, at and
//! above one word per invocation, with runs of whole groups of four words and with a rest.

mod common;

use common::{assert_clean, gpu};
use tessera::scan::ExclusiveScan;
use tessera::shaders;
use tessera_gpu::vk;

#[test]
fn exclusive_scan_matches_the_cpu_and_leaves_the_rest() {
    let gpu = gpu();
    let scan = ExclusiveScan::new(&gpu, &shaders::compiler()).unwrap();
    for count in [1u32, 200, 256, 257, 1100, 5003] {
        // Three more words than scanned: they must stay as they are.
        let values: Vec<u32> = (0..count + 3).map(|i| (i * 7919) % 13).collect();
        let buffer = gpu
            .upload_buffer(
                "scan input",
                bytemuck::cast_slice(&values),
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            )
            .unwrap();
        gpu.submit("scan", |rec| scan.record(rec, &buffer, count))
            .unwrap();
        let scanned = gpu.read_buffer_as::<u32>(&buffer).unwrap();
        let mut expected = values.clone();
        let mut sum = 0;
        for v in &mut expected[..count as usize] {
            (*v, sum) = (sum, sum + *v);
        }
        assert_eq!(scanned, expected, "{count} words");
    }
    assert_clean(&gpu);
}
