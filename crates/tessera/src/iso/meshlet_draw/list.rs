//! The second half of the compute path of every stored-surface draw (meshlets, PMB blocks):
//! the frame's triangle list, filled by the draw's own pass (`list.glsl`), drawn by the shared
//! compute rasterizer and shaded by `direct`'s resolve, so that all these paths and `direct`
//! shade alike.

use super::MeshletDrawParams;
use crate::config::meshlet_draw_defines;
use crate::error::{Error, Result};
use crate::iso::direct::compute::ComputeTarget;
use crate::iso::direct::resolve::{clip_to_world, Lighting, SurfaceResolve};
use crate::raster::ComputeRasterizer;
use crate::target::Target;
use tessera_gpu::{Gpu, Recorder, ShaderCompiler};

pub struct ListResolve {
    rasterizer: ComputeRasterizer,
    resolve: SurfaceResolve,
}

impl ListResolve {
    /// The passes, their pipelines named after `what` draws.
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, what: &str) -> Result<ListResolve> {
        let name = format!("{what} resolve");
        Ok(ListResolve {
            rasterizer: ComputeRasterizer::new(gpu, compiler)?,
            resolve: SurfaceResolve::new(gpu, compiler, &meshlet_draw_defines(), false, &name)?,
        })
    }

    pub(super) fn rasterizer(&self) -> &ComputeRasterizer {
        &self.rasterizer
    }

    /// Refuses `pixels` of another size than `target`'s frame (before anything is recorded).
    pub fn check_sizes(what: &str, target: &ComputeTarget, pixels: &Target) -> Result<()> {
        let frame = &target.frame;
        if (frame.width, frame.height) != (pixels.width, pixels.height) {
            return Err(Error::Invalid(format!(
                "{what}: a {}x{} image for a {}x{} frame",
                pixels.width, pixels.height, frame.width, frame.height
            )));
        }
        Ok(())
    }

    /// Rasterizes `target`'s list (written and followed by a barrier; the pass that wrote it
    /// grew the raster pass's dispatch arguments, and the frame was emptied with
    /// [`crate::raster::RasterFrame::record_begin`] before a barrier ahead of that pass) and shades it
    /// into `pixels` as `params` light it.
    pub fn record(
        &self,
        rec: &Recorder,
        target: &ComputeTarget,
        pixels: &Target,
        params: &MeshletDrawParams,
    ) {
        let frame = &target.frame;
        self.rasterizer
            .record_raster(rec, &target.lists.triangles, &target.lists.counts, frame);
        let list = target.lists.shaded();
        self.resolve
            .record(rec, frame, list, pixels, params.lighting());
        rec.barrier();
    }
}

impl MeshletDrawParams {
    /// The eye, light and world positions the compute path's resolve shades with.
    pub(super) fn lighting(&self) -> Lighting {
        Lighting {
            eye: self.eye_world,
            light: self.light,
            clip_to_world: clip_to_world(&self.grid_to_clip, self.grid_to_world, self.dims),
        }
    }
}
