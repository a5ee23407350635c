//! Drawing through the shared compute rasterizer in tests.

use glam::Vec4;
use tessera::raster::{
    create_counts_buffer, ComputeRasterizer, RasterCounts, RasterFrame, RasterTriangle,
};
use tessera::shaders;
use tessera_gpu::{vk, Buffer, Gpu};

/// The rasterizer, or `None` (said aloud) on a device without 64-bit buffer atomics.
pub fn rasterizer(gpu: &Gpu) -> Option<ComputeRasterizer> {
    if !gpu.caps().buffer_int64_atomics {
        eprintln!(
            "SKIPPED: {} has no 64-bit buffer atomics; the compute rasterizer cannot run",
            gpu.caps().device_name
        );
        return None;
    }
    Some(ComputeRasterizer::new(gpu, &shaders::compiler()).expect("build the rasterizer"))
}

/// The triangle buffer holding `tris` (at least one slot) and a counts buffer saying `count`
/// of them are there.
pub fn upload_triangles(gpu: &Gpu, tris: &[[Vec4; 3]], count: u32) -> (Buffer, Buffer) {
    let mut list: Vec<RasterTriangle> = tris
        .iter()
        .map(|t| RasterTriangle {
            clip: t.map(|c| c.to_array()),
        })
        .collect();
    if list.is_empty() {
        list.push(RasterTriangle::default());
    }
    let triangles = gpu
        .upload_buffer(
            "test triangles",
            bytemuck::cast_slice(&list),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )
        .unwrap();
    let counts = create_counts_buffer(gpu, "test counts").unwrap();
    let initial = RasterCounts {
        triangle_count: count,
        dispatch: [u32::MAX; 3],
    };
    gpu.write_buffer(&counts, bytemuck::bytes_of(&initial))
        .unwrap();
    (triangles, counts)
}

/// Draws the first `count` of `tris` (the buffer holds all of them, at least one slot) into
/// `frame`; returns the frame and the counts buffer as the passes left them.
pub fn draw_into(
    gpu: &Gpu,
    rast: &ComputeRasterizer,
    tris: &[[Vec4; 3]],
    count: u32,
    frame: &RasterFrame,
) -> (Vec<u64>, RasterCounts) {
    let (triangles, counts) = upload_triangles(gpu, tris, count);
    gpu.submit("raster test", |rec| {
        rast.record(rec, &triangles, &counts, frame)
    })
    .unwrap();
    let values = frame.read(gpu).unwrap();
    let args: RasterCounts = bytemuck::pod_read_unaligned(&gpu.read_buffer(&counts).unwrap()[..16]);
    (values, args)
}

pub fn draw(gpu: &Gpu, rast: &ComputeRasterizer, tris: &[[Vec4; 3]], w: u32, h: u32) -> Vec<u64> {
    let frame = RasterFrame::new(gpu, w, h).unwrap();
    let (values, _) = draw_into(gpu, rast, tris, tris.len() as u32, &frame);
    values
}
