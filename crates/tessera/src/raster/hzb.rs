//! Max-depth pyramid (HZB) of the shared compute rasterizer's frame, for occlusion culling
//! that tests boxes against what a first pass drew (`hzb.glsl` describes the layout,
//! `hzb_test.glsl` the test).

use crate::builtin_shader;
use crate::error::Result;
use crate::raster::RasterFrame;
use tessera_gpu::{Binding, Buffer, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// The levels of the pyramid of a `width`×`height` frame: texels per axis, level 0 (half
/// resolution) first, down to 1×1.
pub fn hzb_levels(width: u32, height: u32) -> Vec<[u32; 2]> {
    let mut d = [width.div_ceil(2), height.div_ceil(2)];
    let mut levels = vec![d];
    while d[0] > 1 || d[1] > 1 {
        d = d.map(|n| n.div_ceil(2));
        levels.push(d);
    }
    levels
}

/// Bytes of the pyramid of a `width`×`height` frame (one f32 per texel of every level).
pub fn hzb_bytes(width: u32, height: u32) -> u64 {
    4 * hzb_levels(width, height)
        .iter()
        .map(|d| u64::from(d[0]) * u64::from(d[1]))
        .sum::<u64>()
}

/// Builds the pyramid, one dispatch per level.
pub struct HzbBuilder {
    pipeline: Pipeline,
}

impl HzbBuilder {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<HzbBuilder> {
        let spirv = compiler.compile(&builtin_shader!("hzb_build.comp.glsl"), &[])?;
        Ok(HzbBuilder {
            pipeline: gpu.compute_pipeline("hzb build", &spirv, &[Slot::StorageBuffer; 2])?,
        })
    }

    /// Records the pyramid of `frame` into `hzb` (at least [`hzb_bytes`] long); ends with a
    /// barrier.
    pub fn record(&self, rec: &Recorder, frame: &RasterFrame, hzb: &Buffer) {
        let (w, h) = (frame.width, frame.height);
        for (level, d) in hzb_levels(w, h).iter().enumerate() {
            rec.dispatch(
                &self.pipeline,
                &[Binding::Buffer(&frame.depth_payload), Binding::Buffer(hzb)],
                bytemuck::bytes_of(&[w, h, level as u32, 0]),
                [d[0], d[1], 1],
            );
            rec.barrier();
        }
    }
}
