//! Isosurfaces as persistent meshlets behind the front door (paper C): `meshlets` extracts on
//! the GPU when the isovalue changes and draws the stored meshlets from every view; `offline`
//! draws meshoptimizer meshlets of the CPU marching-cubes mesh, the paper's best-case draw
//! reference. Both draw on the task/mesh path or the compute path
//! ([`crate::iso::meshlet_draw`]); with culling on, meshlets are frustum-culled on both and
//! occlusion-culled on the compute path.

use super::surface_frame::{FrameBuffers, SurfaceDraw, SurfaceFrame, SurfaceLevel};
use super::{
    no_data, wrong_data, FrameOutcome, FrameStats, Renderer, RendererOptions, Target, Technique,
    WorkCounters,
};
use crate::error::{Error, Result};
use crate::iso::meshlet_draw::{
    DrawCounters, MeshletBounds, MeshletDraw, MeshletOcclusion, OcclusionCounters,
};
use crate::iso::meshlets::{
    ExtractionPath, GpuMeshlets, MeshletCounters, MeshletExtractor, OVERFLOW_CAPACITY,
    OVERFLOW_MISMATCH,
};
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::PreparedVolume;
use crate::path::Path;
use std::time::Instant;
use tessera_data::marching_cubes::marching_cubes_with;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::meshlets::offline_meshlets;
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{View, Volume};
use tessera_gpu::{Gpu, Readback, Recorder, Timer};

/// Bytes of [`MeshletCounters`].
const TOTALS_BYTES: u64 = std::mem::size_of::<MeshletCounters>() as u64;

/// How the stored surface was made.
enum Producer {
    /// GPU extraction from the prepared volume.
    Extraction {
        extractor: Box<MeshletExtractor>,
        prepared: Box<PreparedVolume>,
    },
    /// CPU marching cubes and meshoptimizer, uploaded.
    Offline,
}

/// The meshlets on the GPU and the isovalue (texel units) they hold the surface of; NaN
/// until an extraction into them succeeded.
struct StoredSurface {
    meshlets: GpuMeshlets,
    made_at: f32,
}

pub(super) struct MeshletRenderer {
    technique: Technique,
    path: Path,
    bounds: MeshletBounds,
    /// Occlusion culling (compute path, with culling on): its state, made by `prepare_frame`.
    occlusion: Option<MeshletOcclusion>,
    occlusion_culling: bool,
    ambiguity: AmbiguityRule,
    draw: Option<MeshletDraw>,
    volume: Option<Volume>,
    producer: Option<Producer>,
    surface: Option<StoredSurface>,
    /// Whether the frame being recorded extracts the surface anew.
    extracting: bool,
    level: SurfaceLevel,
    /// The extraction's totals, copied to the host at the end of a frame that extracted.
    totals: Option<Readback>,
    frame: SurfaceFrame,
    /// What the offline surface cost on the CPU, in milliseconds.
    extraction_ms: f64,
    stats: FrameStats,
    counters: WorkCounters,
}

impl MeshletRenderer {
    pub(super) fn new(
        gpu: &Gpu,
        technique: Technique,
        options: &RendererOptions,
    ) -> Result<MeshletRenderer> {
        let path = super::path_for(gpu.caps(), technique, options.path)?;
        Ok(MeshletRenderer {
            technique,
            path,
            bounds: if options.culling.enabled() {
                MeshletBounds::Explicit
            } else {
                MeshletBounds::None
            },
            occlusion: None,
            occlusion_culling: options.culling.enabled() && path == Path::Compute,
            ambiguity: options.ambiguity,
            draw: None,
            volume: None,
            producer: None,
            surface: None,
            extracting: false,
            level: SurfaceLevel::new(),
            totals: None,
            frame: SurfaceFrame::new(options.hidden_side),
            extraction_ms: 0.0,
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }

    /// Makes the offline surface for the current isovalue unless it exists (GPU extraction
    /// is recorded into the frame instead, see `record`).
    fn ensure_offline_surface(&mut self, gpu: &Gpu) -> Result<()> {
        let (Some(Producer::Offline), Some(volume)) = (&self.producer, &self.volume) else {
            return Ok(());
        };
        if self
            .surface
            .as_ref()
            .is_some_and(|s| s.made_at == self.level.iso)
        {
            return Ok(());
        }
        self.surface = None;
        let start = Instant::now();
        let mesh = marching_cubes_with(volume, self.level.iso, self.ambiguity);
        let meshlets = offline_meshlets(&mesh)?;
        self.extraction_ms = start.elapsed().as_secs_f64() * 1e3;
        self.surface = Some(StoredSurface {
            meshlets: GpuMeshlets::upload(gpu, &meshlets)?,
            made_at: self.level.iso,
        });
        // Other meshlets under the same indices: what the flags say is void.
        self.occlusion = None;
        Ok(())
    }

    /// Buffers for the GPU extraction, made once per volume (they grow on overflow).
    fn ensure_extraction_buffers(&mut self, gpu: &Gpu) -> Result<()> {
        if let (
            Some(Producer::Extraction {
                extractor,
                prepared,
            }),
            None,
        ) = (&self.producer, &self.surface)
        {
            self.surface = Some(StoredSurface {
                meshlets: extractor.buffers(gpu, prepared, Default::default())?,
                made_at: f32::NAN,
            });
        }
        Ok(())
    }
}

impl Renderer for MeshletRenderer {
    fn technique(&self) -> Technique {
        self.technique
    }

    fn path(&self) -> Path {
        self.path
    }

    fn set_data(&mut self, gpu: &Gpu, data: &Dataset) -> Result<()> {
        let Dataset::Volume(volume) = data else {
            return Err(wrong_data(self.technique, data));
        };
        self.surface = None;
        self.producer = None;
        let compiler = crate::shaders::compiler();
        if self.draw.is_none() {
            self.draw = Some(if self.occlusion_culling {
                MeshletDraw::with_occlusion(gpu, &compiler)?
            } else {
                MeshletDraw::new(gpu, &compiler, self.path)?
            });
            self.counters.pipeline_builds += 1;
        }
        self.occlusion = None;
        let extracts = self.technique != Technique::Offline;
        if extracts && self.totals.is_none() {
            self.totals = Some(gpu.create_readback("meshlet totals (host)", TOTALS_BYTES)?);
        }
        let producer = match self.technique {
            Technique::Offline => Producer::Offline,
            _ => {
                let scalar = volume.scalar_type();
                let builder = MinMaxBuilder::new(gpu, &compiler, scalar)?;
                // Extraction runs on compute whatever the draw path: the same meshlets bit
                // for bit, and the graphics stages of some GPUs run on few units.
                let extractor = MeshletExtractor::new(
                    gpu,
                    &compiler,
                    scalar,
                    self.ambiguity,
                    ExtractionPath::Compute,
                )?;
                self.counters.pipeline_builds += 1;
                Producer::Extraction {
                    extractor: Box::new(extractor),
                    prepared: Box::new(PreparedVolume::new(gpu, &builder, volume)?),
                }
            }
        };
        self.frame.set_boundary_range(match &producer {
            Producer::Extraction { prepared, .. } => prepared.boundary_range,
            Producer::Offline => tessera_data::facing::boundary_range(volume),
        });
        self.producer = Some(producer);
        self.volume = Some(volume.clone());
        self.level.set_volume(volume, &mut self.counters)
    }

    fn set_appearance(&mut self, _gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.level.set_look(look)
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        if self.producer.is_none() {
            return Err(no_data(self.technique));
        }
        self.ensure_offline_surface(gpu)?;
        self.ensure_extraction_buffers(gpu)?;
        self.frame.prepare(gpu, self.path, view)?;
        if let (true, FrameBuffers::Compute(target), Some(surface)) =
            (self.occlusion_culling, &self.frame.buffers, &self.surface)
        {
            let fits = self
                .occlusion
                .as_ref()
                .is_some_and(|o| o.fits(&surface.meshlets, target));
            if !fits {
                self.occlusion = None;
                self.occlusion = Some(MeshletOcclusion::new(
                    gpu,
                    surface.meshlets.capacity.meshlets,
                    target,
                )?);
            }
        }
        Ok(())
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
            return Err(no_data(self.technique));
        };
        // A new isovalue is extracted in the frame that draws it, and drawn without a
        // readback: the draw reads the meshlet count on the GPU.
        self.extracting = surface.made_at != self.level.iso;
        if let (
            true,
            Some(Producer::Extraction {
                extractor,
                prepared,
            }),
        ) = (self.extracting, &self.producer)
        {
            timer.scope(rec, "meshlet extraction", |rec| {
                extractor.record(rec, prepared, self.level.iso, &surface.meshlets)
            })?;
            rec.barrier();
            if let Some(occlusion) = &self.occlusion {
                occlusion.forget();
            }
        }
        let meshlets = &surface.meshlets;
        let surface_draw = SurfaceDraw {
            technique: self.technique,
            scope: "meshlet draw",
            graphics: &|rec, raster, params| draw.record_graphics(rec, meshlets, raster, params),
            compute: &|rec, frame, params| match &self.occlusion {
                Some(occlusion) => {
                    draw.record_compute_culled(rec, meshlets, frame, target, params, occlusion)
                }
                None => draw.record_compute(rec, meshlets, frame, target, params),
            },
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
        if let (true, Some(totals)) = (self.extracting, &self.totals) {
            rec.barrier();
            totals.record_copy(rec, &surface.meshlets.counters, 0, TOTALS_BYTES);
        }
        drawn
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let (Some(draw), Some(surface)) = (&self.draw, &mut self.surface) else {
            return Err(no_data(self.technique));
        };
        let mut retry = false;
        if self.extracting {
            let totals: MeshletCounters = self
                .totals
                .as_ref()
                .and_then(|t| t.bytes().get(..TOTALS_BYTES as usize))
                .map(bytemuck::pod_read_unaligned)
                .ok_or_else(|| Error::Invalid("meshlet extraction: no totals read back".into()))?;
            if totals.overflow & OVERFLOW_MISMATCH != 0 {
                return Err(Error::Invalid(
                    "meshlet extraction: a subblock's extraction counted other vertices or \
                     triangles than its region analysis"
                        .into(),
                ));
            }
            let grew = surface.meshlets.grow_for(gpu, &totals)?;
            if totals.overflow & OVERFLOW_CAPACITY != 0 || grew {
                // The grown buffers are empty: extract into them in the frame again.
                surface.made_at = f32::NAN;
                retry = true;
            } else {
                surface.meshlets.totals = totals;
                surface.made_at = self.level.iso;
            }
        }
        let passes = match &self.occlusion {
            Some(occlusion) => occlusion.read_counters(draw),
            None => OcclusionCounters {
                second: draw.read_counters(),
                ..Default::default()
            },
        };
        let drawn = passes.total();
        let most = passes
            .first
            .triangles_drawn
            .max(passes.second.triangles_drawn);
        if self.frame.grow_for(self.path, most) {
            retry = true;
        }
        if retry {
            return Ok(FrameOutcome::Retry);
        }
        let totals = surface.meshlets.totals;
        let mut details: std::collections::BTreeMap<&'static str, u64> = [
            ("meshlets", u64::from(totals.meshlets)),
            ("meshlets_drawn", u64::from(drawn.meshlets_drawn)),
            ("surface_vertices", u64::from(totals.vertices)),
            ("surface_bytes", totals.stored_bytes()),
        ]
        .into();
        if self.occlusion.is_some() {
            let DrawCounters { meshlets_drawn, .. } = passes.first;
            details.insert("meshlets_drawn_first", u64::from(meshlets_drawn));
            details.insert(
                "meshlets_drawn_second",
                u64::from(passes.second.meshlets_drawn),
            );
        }
        if let Some(one_side) = self.frame.one_side_drawn() {
            details.insert("one_side_drawn", one_side);
        }
        if matches!(self.producer, Some(Producer::Offline)) {
            details.insert(
                "cpu_extraction_us",
                (self.extraction_ms * 1e3).round() as u64,
            );
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
