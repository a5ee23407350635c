//! The max-depth pyramid of the compute rasterizer's frame (`raster/hzb.glsl`) against the
//! CPU's, level by level, on lavapipe or a GPU, with validation on.

mod common;

use common::Rng;
use common::{assert_clean, gpu};
use tessera::raster::hzb::{hzb_bytes, hzb_levels, HzbBuilder};
use tessera::raster::{RasterFrame, EMPTY};
use tessera_gpu::vk;

/// The max-depth pyramid as `raster/hzb.glsl` defines it, level by level on the CPU: each texel
/// the max of its 2×2 sources, the last row or column repeated past the edge.
fn cpu_pyramid(depths: &[f32], w: u32, h: u32) -> Vec<Vec<f32>> {
    let mut levels = Vec::new();
    let (mut src, mut src_dims) = (depths.to_vec(), [w, h]);
    for dims in hzb_levels(w, h) {
        let at = |x: u32, y: u32| {
            src[(y.min(src_dims[1] - 1) * src_dims[0] + x.min(src_dims[0] - 1)) as usize]
        };
        let level: Vec<f32> = (0..dims[1])
            .flat_map(|y| (0..dims[0]).map(move |x| (x, y)))
            .map(|(x, y)| {
                let (x, y) = (2 * x, 2 * y);
                at(x, y)
                    .max(at(x + 1, y))
                    .max(at(x, y + 1))
                    .max(at(x + 1, y + 1))
            })
            .collect();
        (src, src_dims) = (level.clone(), dims);
        levels.push(level);
    }
    levels
}

/// The pyramid of frames of many shapes against the CPU's, level by level; pixels of tiles not
/// marked with the frame's number count as empty (those tiles hold other depths here).
#[test]
fn hzb_pyramid_matches_cpu_levels() {
    let gpu = gpu();
    let builder = HzbBuilder::new(&gpu, &tessera::shaders::compiler()).unwrap();
    let mut rng = Rng::new(0x5eed_4a2b);
    // Odd sides, one pixel wide or high, and frames whose pyramids take one, two and three
    // passes (4200 wide: the second pass's first level spans two workgroups).
    for (w, h) in [
        (1, 1),
        (5, 1),
        (1, 7),
        (33, 17),
        (97, 45),
        (130, 67),
        (4200, 3),
        (300, 200),
    ] {
        let n = (w * h) as usize;
        // Depths in [0, 1) with some pixels empty (the pyramid reads them as 1.0).
        let depths: Vec<f32> = (0..n)
            .map(|_| {
                if rng.unit() < 0.1 {
                    1.0
                } else {
                    rng.unit() as f32
                }
            })
            .collect();
        let payload: Vec<u64> = depths
            .iter()
            .enumerate()
            .map(|(i, &d)| {
                if d == 1.0 {
                    EMPTY
                } else {
                    u64::from(d.to_bits()) << 32 | i as u64
                }
            })
            .collect();
        // Every third tile left unmarked: its pixels count as empty whatever they hold.
        let frame = RasterFrame::new(&gpu, w, h).unwrap();
        let tiles = (frame.tile_frames.size / 4) as usize;
        let unmarked = |t: usize| t % 3 == 2;
        let tile_of = |i: usize| frame.tile_index(i as u32 % w, i as u32 / w);
        let depths: Vec<f32> = depths
            .iter()
            .enumerate()
            .map(|(i, &d)| if unmarked(tile_of(i)) { 1.0 } else { d })
            .collect();
        gpu.submit("begin", |rec| {
            frame.record_begin(rec);
        })
        .unwrap();
        let marks: Vec<u32> = (0..tiles)
            .map(|t| frame.frame_number() - u32::from(unmarked(t)))
            .collect();
        gpu.write_buffer(&frame.depth_payload, bytemuck::cast_slice(&payload))
            .unwrap();
        gpu.write_buffer(&frame.tile_frames, bytemuck::cast_slice(&marks))
            .unwrap();
        let hzb = gpu
            .create_buffer(
                "test hzb",
                hzb_bytes(w, h),
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
                tessera_gpu::MemoryLocation::GpuOnly,
            )
            .unwrap();
        // Poison: a level the builder skipped would keep it.
        gpu.submit("poison hzb", |rec| rec.fill_buffer(&hzb, 0x7fc0_0000))
            .unwrap();
        gpu.submit("hzb", |rec| builder.record(rec, &frame, &hzb))
            .unwrap();
        let got: Vec<f32> = gpu.read_buffer_as(&hzb).unwrap();
        let mut offset = 0;
        for (level, want) in cpu_pyramid(&depths, w, h).iter().enumerate() {
            let got = &got[offset..offset + want.len()];
            for (i, (g, e)) in got.iter().zip(want).enumerate() {
                assert_eq!(
                    g.to_bits(),
                    e.to_bits(),
                    "{w}x{h} level {level} texel {i}: {g} != {e}"
                );
            }
            offset += want.len();
        }
    }
    assert_clean(&gpu);
}
