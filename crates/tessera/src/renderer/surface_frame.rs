//! The frame buffers of the techniques that draw a stored surface (meshlets, PMB): the
//! graphics path's attachments, or the compute path's triangle list and raster frame, whose
//! list grows when a frame drew more triangles than it holds.

use super::{Target, Technique, WorkCounters};
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, TriangleLists};
use crate::iso::direct::RasterTarget;
use crate::iso::meshlet_draw::{MeshletBounds, MeshletDrawParams};
use crate::iso::HiddenSide;
use crate::path::Path;
use tessera_data::scene::Appearance;
use tessera_data::{View, Volume};
use tessera_gpu::{Gpu, Recorder, Timer};

/// How one technique draws its stored surface on each path: into the graphics path's
/// attachments, or through the compute path's list into the frame's pixels.
pub(super) struct SurfaceDraw<'a> {
    pub(super) technique: Technique,
    /// The timer scope of the draw.
    pub(super) scope: &'static str,
    pub(super) graphics: &'a dyn Fn(&Recorder, &RasterTarget, &MeshletDrawParams) -> Result<()>,
    pub(super) compute: &'a dyn Fn(&Recorder, &ComputeTarget, &MeshletDrawParams) -> Result<()>,
}

/// The buffers of one path, made by [`SurfaceFrame::prepare`].
pub(super) enum FrameBuffers {
    None,
    Graphics(Box<RasterTarget>),
    Compute(Box<ComputeTarget>),
}

pub(super) struct SurfaceFrame {
    pub(super) buffers: FrameBuffers,
    /// Compute path: triangles a frame's list holds (grown on overflow).
    capacity: u32,
    /// The range of the volume's boundary samples ([`tessera_data::facing::boundary_range`]):
    /// at an isovalue outside it the surface is closed, and the compute path's raster passes
    /// leave out the side no pixel shows. `None` before a volume.
    boundary_range: Option<(f32, f32)>,
    /// Whether they may ([`crate::renderer::RendererOptions::hidden_side`]).
    hidden_side: HiddenSide,
}

impl SurfaceFrame {
    pub(super) fn new(hidden_side: HiddenSide) -> SurfaceFrame {
        SurfaceFrame {
            buffers: FrameBuffers::None,
            capacity: 0,
            boundary_range: None,
            hidden_side,
        }
    }

    /// Compute path: 1 when the last frame's raster passes left out the side of the surface
    /// no pixel shows, else 0 (a stats detail, `one_side_drawn`); `None` on the graphics path.
    pub(super) fn one_side_drawn(&self) -> Option<u64> {
        match &self.buffers {
            FrameBuffers::Compute(target) => {
                Some(u64::from(target.frame.hidden_winding().is_some()))
            }
            _ => None,
        }
    }

    /// Notes the boundary range of the volume whose surfaces are drawn next (a prepared
    /// volume's, where there is one, so that the faces are scanned once).
    pub(super) fn set_boundary_range(&mut self, range: (f32, f32)) {
        self.boundary_range = Some(range);
    }

    /// Makes the buffers `view` needs on `path`; nothing when they exist.
    pub(super) fn prepare(&mut self, gpu: &Gpu, path: Path, view: &View) -> Result<()> {
        let (w, h) = view.size;
        match path {
            Path::Graphics => {
                let fits = matches!(&self.buffers, FrameBuffers::Graphics(t) if (t.width, t.height) == (w, h));
                if !fits {
                    self.buffers = FrameBuffers::None;
                    self.buffers = FrameBuffers::Graphics(Box::new(RasterTarget::new(gpu, w, h)?));
                }
            }
            Path::Compute => {
                if self.capacity == 0 {
                    self.capacity = TriangleLists::default_capacity(gpu).min(1 << 20);
                }
                let fits = matches!(&self.buffers, FrameBuffers::Compute(t)
                    if (t.frame.width, t.frame.height) == (w, h)
                        && t.lists.capacity == self.capacity);
                if !fits {
                    self.buffers = FrameBuffers::None;
                    self.buffers = FrameBuffers::Compute(Box::new(ComputeTarget::new(
                        gpu,
                        w,
                        h,
                        self.capacity,
                    )?));
                }
            }
        }
        Ok(())
    }

    /// Records `draw` of the surface of `volume` at `iso` (texel units) seen in `view` into
    /// `target`, on the path the buffers were prepared for, in its timer scope (the graphics
    /// path's image is copied to `target` after it).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn record_draw(
        &self,
        rec: &Recorder,
        timer: &mut Timer,
        view: &View,
        (volume, iso): (&Volume, f32),
        bounds: MeshletBounds,
        target: &Target,
        draw: &SurfaceDraw,
    ) -> Result<()> {
        let (dims, spacing) = (volume.dims(), volume.spacing());
        match &self.buffers {
            FrameBuffers::Graphics(raster) => {
                let params = MeshletDrawParams::new(view, dims, spacing, bounds, 0);
                let drawn =
                    timer.scope(rec, draw.scope, |rec| (draw.graphics)(rec, raster, &params));
                raster.record_copy_to(rec, target);
                drawn
            }
            FrameBuffers::Compute(frame) => {
                let params =
                    MeshletDrawParams::new(view, dims, spacing, bounds, frame.lists.capacity);
                let hidden = self
                    .boundary_range
                    .filter(|_| self.hidden_side == HiddenSide::Skip)
                    .and_then(|range| tessera_data::facing::boundary_side(range, iso))
                    .and_then(|side| {
                        let grid_to_clip = glam::Mat4::from_cols_array_2d(&params.grid_to_clip);
                        tessera_data::facing::hidden_winding(grid_to_clip, dims, side)
                    });
                frame.frame.hide_winding(hidden);
                timer.scope(rec, draw.scope, |rec| (draw.compute)(rec, frame, &params))
            }
            FrameBuffers::None => Err(Error::Invalid(format!(
                "{}: record before prepare_frame",
                draw.technique.name()
            ))),
        }
    }

    /// Whether a frame that drew `triangles` on `path` must be drawn again: on the compute
    /// path when they did not fit the list, which then grows (at the next `prepare`).
    pub(super) fn grow_for(&mut self, path: Path, triangles: u32) -> bool {
        if path == Path::Compute && triangles > self.capacity {
            self.capacity = crate::capacity::grown_capacity(self.capacity, triangles);
            return true;
        }
        false
    }
}

/// The isovalue a stored surface is drawn at: the look's, in texel units of the volume's value
/// range.
pub(super) struct SurfaceLevel {
    look: Appearance,
    value_range: (f32, f32),
    pub(super) iso: f32,
}

impl SurfaceLevel {
    pub(super) fn new() -> SurfaceLevel {
        SurfaceLevel {
            look: Appearance::default(),
            value_range: (0.0, 1.0),
            iso: 0.0,
        }
    }

    /// A new volume: its value range, the isovalue in it, and its upload counted.
    pub(super) fn set_volume(
        &mut self,
        volume: &Volume,
        counters: &mut WorkCounters,
    ) -> Result<()> {
        counters.data_uploads += 1;
        counters.data_bytes += volume.size_bytes();
        self.value_range = volume.texel_range();
        self.iso = self.look.iso_in_range(self.value_range)?;
        Ok(())
    }

    pub(super) fn set_look(&mut self, look: &Appearance) -> Result<()> {
        self.look = look.clone();
        self.iso = self.look.iso_in_range(self.value_range)?;
        Ok(())
    }
}
