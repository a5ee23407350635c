//! Max-depth pyramid (HZB) of the shared compute rasterizer's frame, for occlusion culling
//! that tests boxes against what a first pass drew (`hzb.glsl` describes the layout,
//! `hzb_test.glsl` the test).

use crate::builtin_shader;
use crate::error::Result;
use crate::raster::RasterFrame;
use bytemuck::{Pod, Zeroable};
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

/// Invocations per side of a pyramid-building workgroup; each folds a 2×2 of its pass's first
/// level, so a pass builds `HZB_TILE.ilog2() + 2` levels.
const HZB_TILE: u32 = 16;

/// Levels one dispatch of the builder makes (the frame's 2×2 → a 32×32 tile → … → 1×1).
pub const HZB_LEVELS_PER_PASS: usize = HZB_TILE.ilog2() as usize + 2;

pub(crate) fn build_defines() -> Vec<(String, String)> {
    vec![
        ("HZB_TILE".into(), format!("{HZB_TILE}u")),
        ("RASTER_TILE".into(), format!("{}u", super::RASTER_TILE)),
    ]
}

/// Push constants of `hzb_build.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct HzbBuildParams {
    pub(crate) size: [u32; 2],
    pub(crate) first_level: u32,
    pub(crate) level_count: u32,
    /// [`RasterFrame::frame_number`].
    pub(crate) frame_number: u32,
}

/// Builds the pyramid, [`HZB_LEVELS_PER_PASS`] levels per dispatch (a barrier between
/// dispatches costs more than the pyramid's small levels do).
pub struct HzbBuilder {
    pipeline: Pipeline,
}

impl HzbBuilder {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<HzbBuilder> {
        let spirv = compiler.compile(&builtin_shader!("hzb_build.comp.glsl"), &build_defines())?;
        Ok(HzbBuilder {
            pipeline: gpu.compute_pipeline("hzb build", &spirv, &[Slot::StorageBuffer; 3])?,
        })
    }

    /// Records the pyramid of `frame` into `hzb` (at least [`hzb_bytes`] long); ends with a
    /// barrier. Only the tiles marked with the frame's number are read (the rest are empty).
    pub fn record(&self, rec: &Recorder, frame: &RasterFrame, hzb: &Buffer) {
        let (w, h) = (frame.width, frame.height);
        let levels = hzb_levels(w, h);
        let tile = 2 * HZB_TILE;
        for (pass, dims) in levels.chunks(HZB_LEVELS_PER_PASS).enumerate() {
            let params = HzbBuildParams {
                size: [w, h],
                first_level: (pass * HZB_LEVELS_PER_PASS) as u32,
                level_count: dims.len() as u32,
                frame_number: frame.frame_number(),
            };
            let first = dims[0];
            rec.dispatch_groups(
                &self.pipeline,
                &[
                    Binding::Buffer(&frame.depth_payload),
                    Binding::Buffer(hzb),
                    Binding::Buffer(&frame.tile_frames),
                ],
                bytemuck::bytes_of(&params),
                [first[0].div_ceil(tile), first[1].div_ceil(tile), 1],
            );
            rec.barrier();
        }
    }
}
