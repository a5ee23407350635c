//! Isosurfaces as Parallel Marching Blocks behind the front door (paper C's real-time
//! reference): `pmb` extracts a PMB mesh on the GPU inside the frame whose isovalue changed,
//! and draws the stored blocks from every view ([`crate::iso::pmb_draw`]) on the graphics
//! path (indexed indirect draws) or the compute path.

use super::surface_frame::{SurfaceDraw, SurfaceFrame, SurfaceLevel};
use super::{
    no_data, wrong_data, FrameOutcome, FrameStats, Renderer, RendererOptions, Target, Technique,
    WorkCounters,
};
use crate::error::{Error, Result};
use crate::iso::meshlet_draw::MeshletBounds;
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::pmb::{GpuPmb, PmbBlockSize, PmbCounters, PmbExtractor};
use crate::iso::pmb_draw::PmbDraw;
use crate::iso::PreparedVolume;
use crate::path::Path;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{View, Volume};
use tessera_gpu::{Gpu, Readback, Recorder, Timer};

/// The extraction's pipelines and buffers for one volume.
struct Surface {
    extractor: PmbExtractor,
    prepared: PreparedVolume,
    pmb: GpuPmb,
    /// The isovalue (texel units) `pmb` holds the surface of; NaN until an extraction into
    /// the current buffers succeeded.
    made_at: f32,
    /// The extraction's totals, copied to the host at the end of a frame that extracted.
    totals: Readback,
}

/// Bytes of [`PmbCounters`].
const TOTALS_BYTES: u64 = std::mem::size_of::<PmbCounters>() as u64;

pub(super) struct PmbRenderer {
    path: Path,
    bounds: MeshletBounds,
    ambiguity: AmbiguityRule,
    block_size: PmbBlockSize,
    draw: Option<PmbDraw>,
    volume: Option<Volume>,
    surface: Option<Surface>,
    /// Whether the frame being recorded extracts the surface anew.
    extracting: bool,
    level: SurfaceLevel,
    frame: SurfaceFrame,
    stats: FrameStats,
    counters: WorkCounters,
}

const TECHNIQUE: Technique = Technique::Pmb;

impl PmbRenderer {
    pub(super) fn new(gpu: &Gpu, options: &RendererOptions) -> Result<PmbRenderer> {
        Ok(PmbRenderer {
            path: super::path_for(gpu.caps(), TECHNIQUE, options.path)?,
            // Blocks store no bounds: the box of their cells is the implicit one.
            bounds: if options.culling.enabled() {
                MeshletBounds::Implicit
            } else {
                MeshletBounds::None
            },
            ambiguity: options.ambiguity,
            block_size: options.pmb_block,
            draw: None,
            volume: None,
            surface: None,
            extracting: false,
            level: SurfaceLevel::new(),
            frame: SurfaceFrame::new(options.hidden_side),
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }
}

impl Renderer for PmbRenderer {
    fn technique(&self) -> Technique {
        TECHNIQUE
    }

    fn path(&self) -> Path {
        self.path
    }

    fn set_data(&mut self, gpu: &Gpu, data: &Dataset) -> Result<()> {
        let Dataset::Volume(volume) = data else {
            return Err(wrong_data(TECHNIQUE, data));
        };
        self.surface = None;
        let compiler = crate::shaders::compiler();
        if self.draw.is_none() {
            self.draw = Some(PmbDraw::new(gpu, &compiler, self.path, self.block_size)?);
            self.counters.pipeline_builds += 1;
        }
        let scalar = volume.scalar_type();
        let builder = MinMaxBuilder::new(gpu, &compiler, scalar)?;
        let extractor = PmbExtractor::new(gpu, &compiler, scalar, self.ambiguity, self.block_size)?;
        self.counters.pipeline_builds += 1;
        let prepared = PreparedVolume::new(gpu, &builder, volume)?;
        self.frame.set_boundary_range(prepared.boundary_range);
        let pmb = extractor.buffers(gpu, &prepared, Default::default())?;
        if let Some(draw) = &mut self.draw {
            draw.prepare(gpu, &pmb)?;
        }
        let totals = gpu.create_readback("PMB totals (host)", TOTALS_BYTES)?;
        self.surface = Some(Surface {
            totals,
            extractor,
            prepared,
            pmb,
            made_at: f32::NAN,
        });
        self.volume = Some(volume.clone());
        self.level.set_volume(volume, &mut self.counters)
    }

    fn set_appearance(&mut self, _gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.level.set_look(look)
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        let (Some(draw), Some(surface)) = (&mut self.draw, &self.surface) else {
            return Err(no_data(TECHNIQUE));
        };
        // The buffers may have grown since the last frame.
        draw.prepare(gpu, &surface.pmb)?;
        self.frame.prepare(gpu, self.path, view)
    }

    fn record(
        &mut self,
        rec: &Recorder,
        view: &View,
        target: &Target,
        timer: &mut Timer,
    ) -> Result<()> {
        let (Some(draw), Some(surface), Some(volume)) = (&self.draw, &self.surface, &self.volume)
        else {
            return Err(no_data(TECHNIQUE));
        };
        // A new isovalue is extracted in the frame that draws it, and drawn without a
        // readback: the draw reads the block count on the GPU.
        self.extracting = surface.made_at != self.level.iso;
        if self.extracting {
            timer.scope(rec, "PMB extraction", |rec| {
                surface
                    .extractor
                    .record(rec, &surface.prepared, self.level.iso, &surface.pmb)
            });
            rec.barrier();
        }
        let pmb = &surface.pmb;
        let surface_draw = SurfaceDraw {
            technique: TECHNIQUE,
            scope: "PMB draw",
            graphics: &|rec, raster, params| draw.record_graphics(rec, pmb, raster, params),
            compute: &|rec, frame, params| draw.record_compute(rec, pmb, frame, target, params),
        };
        let drawn = self.frame.record_draw(
            rec,
            timer,
            view,
            (volume, self.level.iso),
            self.bounds,
            target,
            &surface_draw,
        );
        if self.extracting {
            rec.barrier();
            surface
                .totals
                .record_copy(rec, &surface.pmb.counters, 0, TOTALS_BYTES);
        }
        drawn
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let (Some(draw), Some(surface)) = (&self.draw, &mut self.surface) else {
            return Err(no_data(TECHNIQUE));
        };
        let mut retry = false;
        if self.extracting {
            let totals: PmbCounters = surface
                .totals
                .bytes()
                .get(..TOTALS_BYTES as usize)
                .map(bytemuck::pod_read_unaligned)
                .ok_or_else(|| Error::Invalid("PMB extraction: no totals read back".into()))?;
            let grew = surface.pmb.grow_for(gpu, &totals)?;
            if totals.overflow != 0 || grew {
                // The grown buffers are empty: extract into them in the frame again.
                surface.made_at = f32::NAN;
                retry = true;
            } else {
                surface.pmb.totals = totals;
                surface.made_at = self.level.iso;
            }
        }
        let drawn = draw.read_counters();
        if self.frame.grow_for(self.path, drawn.triangles_drawn) {
            retry = true;
        }
        if retry {
            return Ok(FrameOutcome::Retry);
        }
        let totals = surface.pmb.totals;
        let mut details: std::collections::BTreeMap<&'static str, u64> = [
            ("blocks", u64::from(totals.blocks)),
            ("blocks_drawn", u64::from(drawn.blocks_drawn)),
            ("surface_vertices", u64::from(totals.vertices)),
            ("surface_triangles", u64::from(totals.triangles)),
            ("surface_bytes", totals.stored_bytes()),
        ]
        .into();
        if let Some(one_side) = self.frame.one_side_drawn() {
            details.insert("one_side_drawn", one_side);
        }
        self.stats = FrameStats {
            triangles: Some(u64::from(drawn.triangles_drawn)),
            details,
            ..FrameStats::default()
        };
        Ok(FrameOutcome::Done)
    }

    fn stats(&self) -> FrameStats {
        self.stats.clone()
    }

    fn counters(&self) -> WorkCounters {
        self.counters
    }
}
