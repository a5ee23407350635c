//! Isosurfaces as persistent meshlets behind the front door (paper C): `meshlets` extracts on
//! the GPU when the isovalue changes and draws the stored meshlets from every view; `offline`
//! draws meshoptimizer meshlets of the CPU marching-cubes mesh, the paper's best-case draw
//! reference. Both draw on the task/mesh path or the compute path
//! ([`crate::iso::meshlet_draw`]).

use super::{
    no_data, wrong_data, FrameOutcome, FrameStats, Renderer, RendererOptions, Target, Technique,
    WorkCounters,
};
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, TriangleLists};
use crate::iso::direct::RasterTarget;
use crate::iso::meshlet_draw::{MeshletBounds, MeshletDraw, MeshletDrawParams};
use crate::iso::meshlets::{ExtractionPath, GpuMeshlets, MeshletExtractor};
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::PreparedVolume;
use crate::path::Path;
use std::time::Instant;
use tessera_data::marching_cubes::marching_cubes_with;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::meshlets::offline_meshlets;
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{View, Volume};
use tessera_gpu::{Gpu, Recorder, Timer};

/// The frame's buffers for the drawing path, made by `prepare_frame`.
enum FrameBuffers {
    None,
    Graphics(Box<RasterTarget>),
    Compute(Box<ComputeTarget>),
}

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

pub(super) struct MeshletRenderer {
    technique: Technique,
    path: Path,
    bounds: MeshletBounds,
    ambiguity: AmbiguityRule,
    draw: Option<MeshletDraw>,
    volume: Option<Volume>,
    producer: Option<Producer>,
    /// The stored surface and the isovalue (texel units) it was made at.
    surface: Option<(GpuMeshlets, f32)>,
    look: Appearance,
    iso: f32,
    value_range: (f32, f32),
    frame: FrameBuffers,
    /// Compute path: triangles a frame's list holds (grown on overflow).
    capacity: u32,
    /// What the last surface cost: GPU (or CPU, offline) milliseconds and bytes stored.
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
            bounds: if options.culling {
                MeshletBounds::Explicit
            } else {
                MeshletBounds::None
            },
            ambiguity: options.ambiguity,
            draw: None,
            volume: None,
            producer: None,
            surface: None,
            look: Appearance::default(),
            iso: 0.0,
            value_range: (0.0, 1.0),
            frame: FrameBuffers::None,
            capacity: 0,
            extraction_ms: 0.0,
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }

    /// Makes the stored surface for the current isovalue unless it exists.
    fn ensure_surface(&mut self, gpu: &Gpu) -> Result<()> {
        if self.surface.as_ref().is_some_and(|s| s.1 == self.iso) {
            return Ok(());
        }
        let (Some(producer), Some(volume)) = (&self.producer, &self.volume) else {
            return Err(no_data(self.technique));
        };
        let iso = self.iso;
        let surface = match producer {
            Producer::Extraction {
                extractor,
                prepared,
            } => {
                let mut out = match self.surface.take() {
                    Some((out, _)) => out,
                    None => extractor.buffers(gpu, prepared, Default::default())?,
                };
                let extraction = extractor.extract_into(gpu, prepared, iso, &mut out)?;
                self.extraction_ms = extraction.gpu_ms;
                out
            }
            Producer::Offline => {
                self.surface = None;
                let start = Instant::now();
                let mesh = marching_cubes_with(volume, iso, self.ambiguity);
                let meshlets = offline_meshlets(&mesh)?;
                self.extraction_ms = start.elapsed().as_secs_f64() * 1e3;
                GpuMeshlets::upload(gpu, &meshlets)?
            }
        };
        self.surface = Some((surface, iso));
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
            self.draw = Some(MeshletDraw::new(gpu, &compiler, self.path)?);
            self.counters.pipeline_builds += 1;
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
        self.producer = Some(producer);
        self.volume = Some(volume.clone());
        self.counters.data_uploads += 1;
        self.counters.data_bytes += volume.size_bytes();
        self.value_range = volume.texel_range();
        self.iso = self.look.iso_in_range(self.value_range)?;
        Ok(())
    }

    fn set_appearance(&mut self, _gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.look = look.clone();
        self.iso = self.look.iso_in_range(self.value_range)?;
        Ok(())
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        self.ensure_surface(gpu)?;
        let (w, h) = view.size;
        match self.path {
            Path::Graphics => {
                let fits = matches!(&self.frame, FrameBuffers::Graphics(t) if (t.width, t.height) == (w, h));
                if !fits {
                    self.frame = FrameBuffers::None;
                    self.frame = FrameBuffers::Graphics(Box::new(RasterTarget::new(gpu, w, h)?));
                }
            }
            Path::Compute => {
                if self.capacity == 0 {
                    self.capacity = TriangleLists::default_capacity(gpu).min(1 << 20);
                }
                let fits = matches!(&self.frame, FrameBuffers::Compute(t)
                    if (t.frame.width, t.frame.height) == (w, h)
                        && t.lists.capacity == self.capacity);
                if !fits {
                    self.frame = FrameBuffers::None;
                    self.frame = FrameBuffers::Compute(Box::new(ComputeTarget::new(
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

    fn record(
        &mut self,
        rec: &Recorder,
        view: &View,
        target: &Target,
        timer: &mut Timer,
    ) -> Result<()> {
        let (Some(draw), Some((surface, _)), Some(volume)) =
            (&self.draw, &self.surface, &self.volume)
        else {
            return Err(no_data(self.technique));
        };
        let (dims, spacing) = (volume.dims(), volume.spacing());
        match &self.frame {
            FrameBuffers::Graphics(raster) => {
                let params = MeshletDrawParams::new(view, dims, spacing, self.bounds, 0);
                let drawn = timer.scope(rec, "meshlet draw", |rec| {
                    draw.record_graphics(rec, surface, raster, &params)
                });
                raster.record_copy_to(rec, target);
                drawn
            }
            FrameBuffers::Compute(frame) => {
                let params =
                    MeshletDrawParams::new(view, dims, spacing, self.bounds, frame.lists.capacity);
                timer.scope(rec, "meshlet draw", |rec| {
                    draw.record_compute(rec, surface, frame, target, &params)
                })
            }
            FrameBuffers::None => Err(Error::Invalid(format!(
                "{}: record before prepare_frame",
                self.technique.name()
            ))),
        }
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let (Some(draw), Some((surface, _))) = (&self.draw, &self.surface) else {
            return Err(no_data(self.technique));
        };
        let drawn = draw.read_counters(gpu)?;
        if self.path == Path::Compute && drawn.triangles > self.capacity {
            self.capacity = drawn.triangles.saturating_add(drawn.triangles / 4);
            return Ok(FrameOutcome::Retry);
        }
        let totals = surface.totals;
        self.stats = FrameStats {
            triangles: Some(u64::from(drawn.triangles)),
            details: [
                ("meshlets", u64::from(totals.meshlets)),
                ("meshlets_drawn", u64::from(drawn.meshlets)),
                ("surface_vertices", u64::from(totals.vertices)),
                ("surface_bytes", totals.stored_bytes()),
                ("extraction_us", (self.extraction_ms * 1e3).round() as u64),
            ]
            .into(),
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
