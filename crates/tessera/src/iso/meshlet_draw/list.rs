//! The second half of the compute path of every stored-surface draw (meshlets, PMB blocks):
//! the frame's triangle list, filled by the draw's own pass (`list.glsl`), drawn by the shared
//! compute rasterizer and shaded by `direct`'s resolve, so that all these paths and `direct`
//! shade alike.

use super::MeshletDrawParams;
use crate::builtin_shader;
use crate::config::meshlet_draw_defines;
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, ResolveParams};
use crate::raster::{resolve_groups, ComputeRasterizer, RasterFrame};
use crate::target::Target;
use tessera_gpu::{Binding, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

pub struct ListResolve {
    rasterizer: ComputeRasterizer,
    resolve: Pipeline,
}

impl ListResolve {
    /// The passes, their pipelines named after `what` draws.
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler, what: &str) -> Result<ListResolve> {
        let resolve = compiler.compile(
            &builtin_shader!("../direct/resolve.comp.glsl"),
            &meshlet_draw_defines(),
        )?;
        Ok(ListResolve {
            rasterizer: ComputeRasterizer::new(gpu, compiler)?,
            resolve: gpu.compute_pipeline(
                &format!("{what} resolve"),
                &resolve,
                &[Slot::StorageBuffer; 4],
            )?,
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
    /// [`RasterFrame::record_fill_empty`] before a barrier ahead of that pass) and shades it
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
        let shading = resolve_params(params, frame, 0);
        rec.dispatch_groups(
            &self.resolve,
            &[
                Binding::Buffer(&frame.depth_payload),
                Binding::Buffer(&target.lists.triangles),
                Binding::Buffer(&target.lists.attributes),
                Binding::Buffer(&pixels.pixels),
            ],
            bytemuck::bytes_of(&shading),
            resolve_groups(frame.width, frame.height, self.resolve.local_size[0]),
        );
        rec.barrier();
    }
}

/// The shading of `direct`'s resolve for a draw with `params` into `frame`; `second_list` is
/// the index base of the second triangle list (occlusion culling), 0 without one.
pub(super) fn resolve_params(
    params: &MeshletDrawParams,
    frame: &RasterFrame,
    second_list: u32,
) -> ResolveParams {
    let (e, l) = (params.eye_world, params.light);
    ResolveParams {
        eye_world: [e[0], e[1], e[2], 0.0],
        light: [l[0], l[1], l[2], 0.0],
        size: [frame.width, frame.height, second_list, 0],
    }
}
