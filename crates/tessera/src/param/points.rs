//! The RENDERING stage of the POINT-BASED variant (paper E §4.3) and its resolve.
//!
//! `points.comp.glsl`: one 64-invocation workgroup per patch to render (indirect, from the LOD
//! stage's render list) samples the patch on an `(n_u + 1) × (n_v + 1)` grid with
//! `n = ceil(extent · density)` (at most `max_side`) and writes into a [`RasterFrame`]-layout
//! buffer with a 64-bit `atomicMin` of `depth bits << 32 | payload`:
//! * [`Footprint::Cell`] (default): each grid cell is drawn as two triangles at pixel centres,
//!   so coverage and visibility are those of the surface seen through the pixel centres (a
//!   sub-pixel tessellation drawn by the point pass rather than a rasterizer);
//! * [`Footprint::Pixel`] (the paper's): each sample writes the pixel it falls in. Holes appear
//!   unless `density` is well above 1, and silhouettes grow by up to a pixel, since a pixel is
//!   covered when any sample lands in it rather than when its centre is on the surface.
//!
//! Payload (`payload.glsl`): the object index in the high `32 − 2b` bits, then `u` and `v`
//! quantized over the object's domain to `b` bits each, `b = min(16, (32 − object bits) / 2)`
//! (16 bits per parameter for one object, 8 for 19,600 glyphs). The resolve re-evaluates the
//! function there, so colour, normal and shading cost nothing in the point pass and no
//! per-sample attributes are stored.
//!
//! `resolve.comp.glsl`: per image pixel, the average of its `k × k` raster samples, each
//! background or shaded at its decoded `(object, u, v)`: finite-difference normal of the
//! world-space surface, base colour (by direction for glyphs), two-sided Lambert + ambient.

use super::lod::LodStage;
use super::scene::{scene_defines, GpuParamScene};
use crate::builtin_shader;
use crate::error::Result;
use crate::raster::RasterFrame;
use crate::target::Target;
use bytemuck::{Pod, Zeroable};
use tessera_data::param::reference::{AMBIENT, DIFFUSE};
use tessera_data::View;
use tessera_gpu::{Binding, Gpu, Pipeline, Recorder, ShaderCompiler, Slot};

/// How a sample reaches the raster.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Footprint {
    /// Sample-grid cells drawn as two triangles at pixel centres.
    Cell,
    /// Each sample writes the pixel it falls in (paper E).
    Pixel,
}

impl Footprint {
    fn code(self) -> u32 {
        match self {
            Footprint::Cell => 0,
            Footprint::Pixel => 1,
        }
    }
}

/// Push constants of `points.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct PointsParams {
    pub world_to_clip: [[f32; 4]; 4],
    pub viewport: [f32; 2],
    pub density: f32,
    pub max_side: u32,
    pub raster: [u32; 2],
    pub uv_bits: u32,
    pub render_capacity: u32,
    pub footprint: u32,
    pub pad: [u32; 3],
    /// The camera's position (w 1): which way a glyph's cells face.
    pub eye: [f32; 4],
}

/// Push constants of `resolve.comp.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ResolveParams {
    pub eye: [f32; 4],
    pub light: [f32; 4],
    pub background: [f32; 4],
    pub size: [u32; 2],
    pub supersample: u32,
    pub uv_bits: u32,
}

/// The depth|payload raster a point frame draws into (its image is the caller's `Target`).
pub struct PointsFrame {
    pub raster: RasterFrame,
}

impl PointsFrame {
    /// The raster of `view`'s size.
    pub fn new(gpu: &Gpu, view: &View) -> Result<PointsFrame> {
        let (rw, rh) = view.raster_size();
        Ok(PointsFrame {
            raster: RasterFrame::new(gpu, rw, rh)?,
        })
    }
}

/// Samples per pixel along an SH glyph's bounding sphere with which a patch the LOD stage kept
/// whole is drawn at least (`param/min_extent.glsl`). Measured on an 8×8 field of order-8
/// glyphs at 256² against ray tracing: 1.0 gave a silhouette IoU of 0.977, 1.5 gave 0.991,
/// 2.0 gave 0.994; the cost falls on fields of many small glyphs.
pub const MIN_EXTENT_FACTOR: f32 = 1.5;

/// Defines of the point pass and the resolve.
pub fn points_defines() -> Vec<(String, String)> {
    let mut d = scene_defines();
    d.extend([
        (
            "FOOTPRINT_CELL".into(),
            format!("{}u", Footprint::Cell.code()),
        ),
        (
            "FOOTPRINT_PIXEL".into(),
            format!("{}u", Footprint::Pixel.code()),
        ),
        (
            "PARAM_MIN_EXTENT_FACTOR".into(),
            format!("{MIN_EXTENT_FACTOR:?}"),
        ),
        ("SHADE_AMBIENT".into(), format!("{AMBIENT:?}")),
        ("SHADE_DIFFUSE".into(), format!("{DIFFUSE:?}")),
    ]);
    d
}

pub struct PointPasses {
    points: Pipeline,
    resolve: Pipeline,
}

impl PointPasses {
    pub fn new(gpu: &Gpu, compiler: &ShaderCompiler) -> Result<PointPasses> {
        let defines = points_defines();
        let points = compiler.compile(&builtin_shader!("points.comp.glsl"), &defines)?;
        let resolve = compiler.compile(&builtin_shader!("resolve.comp.glsl"), &defines)?;
        let points = gpu.compute_pipeline("param points", &points, &[Slot::StorageBuffer; 6])?;
        let resolve =
            gpu.compute_pipeline("param points resolve", &resolve, &[Slot::StorageBuffer; 5])?;
        Ok(PointPasses { points, resolve })
    }

    /// Clears the raster and draws the LOD stage's render list into it. The LOD stage must have
    /// been recorded before (its render dispatch arguments).
    #[allow(clippy::too_many_arguments)]
    pub fn record_points(
        &self,
        rec: &Recorder,
        lod: &LodStage,
        scene: &GpuParamScene,
        view: &View,
        frame: &PointsFrame,
        footprint: Footprint,
        density: f32,
        max_side: u32,
    ) {
        rec.fill_buffer(&frame.raster.depth_payload, u32::MAX);
        rec.barrier();
        let [objects, values, table] = lod.scene_bindings(scene);
        let params = PointsParams {
            world_to_clip: view.world_to_clip.to_cols_array_2d(),
            viewport: view.viewport().to_array(),
            density,
            max_side,
            raster: [frame.raster.width, frame.raster.height],
            uv_bits: scene.uv_bits,
            render_capacity: lod.settings.capacity,
            footprint: footprint.code(),
            pad: [0; 3],
            eye: view.eye.extend(1.0).to_array(),
        };
        rec.dispatch_indirect(
            &self.points,
            &[
                objects,
                values,
                table,
                Binding::Buffer(&lod.state),
                Binding::Buffer(&lod.render),
                Binding::Buffer(&frame.raster.depth_payload),
            ],
            bytemuck::bytes_of(&params),
            &lod.state,
            LodStage::dispatch_offset(0),
        );
        rec.barrier();
    }

    /// Shades the raster the points pass drew into the image.
    #[allow(clippy::too_many_arguments)]
    pub fn record_resolve(
        &self,
        rec: &Recorder,
        lod: &LodStage,
        scene: &GpuParamScene,
        view: &View,
        frame: &PointsFrame,
        pixels: &Target,
        background: [f32; 3],
    ) {
        let [objects, values, table] = lod.scene_bindings(scene);
        let resolve = ResolveParams {
            eye: view.eye.extend(1.0).to_array(),
            light: view.light.extend(0.0).to_array(),
            background: [background[0], background[1], background[2], 1.0],
            size: [view.size.0, view.size.1],
            supersample: view.supersample,
            uv_bits: scene.uv_bits,
        };
        rec.dispatch(
            &self.resolve,
            &[
                objects,
                values,
                table,
                Binding::Buffer(&frame.raster.depth_payload),
                Binding::Buffer(&pixels.pixels),
            ],
            bytemuck::bytes_of(&resolve),
            [view.size.0, view.size.1, 1],
        );
        rec.barrier();
    }
}
