//! Tet meshes behind the front door: interval shading (paper A) on its mesh-shader or compute
//! path. The integrand's kind is compiled into the pipelines, so only a change of kind (e.g.
//! absorption to maximum) builds them again; a new transfer function, density or scalar range
//! is a table write and a push constant.

use super::{
    no_data, wrong_data, AccumulatedQuantity, Accumulation, FrameOutcome, FrameStats, Renderer,
    RendererOptions, Target, Technique, WorkCounters,
};
use crate::error::{Error, Result};
use crate::path::Path;
use crate::tet::interval::scheme_choice::{AutoScheme, DrawScheme};
use crate::tet::interval::{
    ComputeScheme, GpuTetMesh, Integrand, Interval, IntervalOptions, IntervalTuning, OpticalTarget,
};
use tessera_data::scene::{Appearance, DataKind, Dataset, ResolvedIntegrand, TetData};
use tessera_data::transfer::ScalarMode;
use tessera_data::View;
use tessera_gpu::{Gpu, Recorder, Timer};

/// What the renderer keeps of the data set: the mesh (the integrand's rules look at its scalars
/// and colours) and its upload.
struct MeshOnGpu {
    data: TetData,
    mesh: GpuTetMesh,
}

pub(super) struct IntervalRenderer {
    path: Path,
    tuning: IntervalTuning,
    data: Option<MeshOnGpu>,
    look: Appearance,
    /// Built for the integrand of the current look.
    pipelines: Option<Interval>,
    /// The absorption colour of the look last applied (`None`: the mesh's own).
    absorption: Option<[f32; 3]>,
    background: [f32; 3],
    accumulation: Option<OpticalTarget>,
    /// Compute path with the automatic scheme: the choice, the timer of each frame's drawing
    /// it rests on, and the scheme of the last recorded frame.
    auto_scheme: Option<(AutoScheme, Timer)>,
    last_scheme: DrawScheme,
    stats: FrameStats,
    counters: WorkCounters,
}

impl IntervalRenderer {
    pub(super) fn new(gpu: &Gpu, options: &RendererOptions) -> Result<IntervalRenderer> {
        let path = super::path_for(gpu.caps(), Technique::Interval, options.path)?;
        let scheme = options.interval.compute_scheme;
        let auto_scheme = if path == Path::Compute && scheme == ComputeScheme::Auto {
            let mut timer = Timer::new(gpu, 1)?;
            timer.reset(gpu);
            Some((AutoScheme::default(), timer))
        } else {
            None
        };
        Ok(IntervalRenderer {
            auto_scheme,
            last_scheme: scheme.first_draw(),
            path,
            tuning: options.interval,
            data: None,
            look: Appearance::default(),
            pipelines: None,
            absorption: None,
            background: [0.0; 3],
            accumulation: None,
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }

    /// Resolves the look against the mesh; builds the pipelines when the integrand's kind
    /// changed, else writes the new table.
    fn apply_look(&mut self, gpu: &Gpu) -> Result<()> {
        let Some(data) = &mut self.data else {
            return Ok(());
        };
        let resolved = self.look.resolve_integrand(&data.data)?;
        let integrand = match &resolved {
            ResolvedIntegrand::TetAbsorption => Integrand::TetAbsorption,
            ResolvedIntegrand::Asteroids => Integrand::Asteroids,
            ResolvedIntegrand::Scalar { mode, table, range } => {
                data.mesh.scalar_range = *range;
                Integrand::Scalar {
                    mode: *mode,
                    table: table.clone(),
                }
            }
        };
        let rebuild = match &self.pipelines {
            Some(p) => !p.can_switch_to(&integrand),
            None => true,
        };
        if rebuild {
            self.pipelines = None;
            let options = IntervalOptions {
                integrand,
                ..IntervalOptions::tuned(self.path, self.tuning)
            };
            self.pipelines = Some(Interval::new(gpu, &crate::shaders::compiler(), &options)?);
            self.counters.pipeline_builds += 1;
            // The accumulation's kind (depth-tested or not) follows the integrand.
            self.accumulation = None;
        } else if let Some(p) = &mut self.pipelines {
            p.set_table(gpu, &integrand)?;
        }
        if self.look.absorption != self.absorption {
            match self.look.absorption {
                Some(colour) => data.mesh.write_absorption(gpu, colour)?,
                None => data.mesh.write_absorption_of(gpu, &data.data.mesh)?,
            }
            self.absorption = self.look.absorption;
        }
        self.background = self.look.background(DataKind::Tets, Some(&resolved));
        Ok(())
    }
}

impl Renderer for IntervalRenderer {
    fn technique(&self) -> Technique {
        Technique::Interval
    }

    fn path(&self) -> Path {
        self.path
    }

    fn set_data(&mut self, gpu: &Gpu, data: &Dataset) -> Result<()> {
        let Dataset::Tets(tets) = data else {
            return Err(wrong_data(Technique::Interval, data));
        };
        self.data = None;
        let mesh = if tets.asteroids {
            GpuTetMesh::upload_asteroids(gpu, &tets.mesh)?
        } else {
            GpuTetMesh::upload(gpu, &tets.mesh)?
        };
        self.counters.data_uploads += 1;
        self.counters.data_bytes += mesh.bytes();
        if let Some((auto, _)) = &mut self.auto_scheme {
            auto.reset();
        }
        self.data = Some(MeshOnGpu {
            data: tets.clone(),
            mesh,
        });
        self.absorption = None;
        self.apply_look(gpu)
    }

    fn set_appearance(&mut self, gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.look = look.clone();
        self.apply_look(gpu)
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        let pipelines = self
            .pipelines
            .as_ref()
            .ok_or_else(|| no_data(Technique::Interval))?;
        let fits = self
            .accumulation
            .as_ref()
            .is_some_and(|a| (a.width, a.height) == view.size);
        if !fits {
            self.accumulation = None;
            self.accumulation = Some(pipelines.target(gpu, view.size.0, view.size.1)?);
            // Another image size changes what each scheme costs: measure both again.
            if let Some((auto, _)) = &mut self.auto_scheme {
                auto.reset();
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
        let (Some(pipelines), Some(data), Some(accumulation)) =
            (&self.pipelines, &self.data, &self.accumulation)
        else {
            return Err(no_data(Technique::Interval));
        };
        let params = pipelines.params_for_view(&data.mesh, view);
        let recorded = match &mut self.auto_scheme {
            // Timed whole, whichever scheme draws, so that the frame's scopes stay the same.
            Some((auto, own)) => {
                let scheme = auto.next();
                self.last_scheme = scheme;
                let draw = |rec: &Recorder| {
                    pipelines.record_with(rec, &data.mesh, accumulation, &params, scheme, None)
                };
                // Frames recorded before the last is finished all draw with this scheme; the
                // first of them is the one the choice learns from.
                timer.scope(rec, "interval", |rec| {
                    if own.is_full() {
                        draw(rec)
                    } else {
                        own.scope(rec, "drawing", draw)
                    }
                })
            }
            None => pipelines.record(rec, &data.mesh, accumulation, &params, Some(timer)),
        };
        timer.scope(rec, "composite", |rec| {
            pipelines.record_composite(rec, accumulation, target, self.background)
        });
        recorded
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let pipelines = self
            .pipelines
            .as_mut()
            .ok_or_else(|| no_data(Technique::Interval))?;
        let counts = pipelines.read_counts(gpu)?;
        // The frame is complete (the per-tet passes drew what the binned lists had no room
        // for); the lists grow for the next one.
        let overflowed = match &self.accumulation {
            Some(accumulation) => {
                pipelines.grow_buffers(gpu, (accumulation.width, accumulation.height))?
            }
            None => false,
        };
        if let Some((auto, own)) = &mut self.auto_scheme {
            if let Some(&(_, ms)) = own.read_ms(gpu)?.first() {
                auto.after_frame(self.last_scheme, ms, overflowed);
            }
            own.reset(gpu);
        }
        let binned = self.last_scheme == DrawScheme::Binned;
        self.stats = FrameStats {
            tets_clipped: Some(u64::from(counts.clipped_near)),
            details: [
                ("tiled_tets", u64::from(counts.tiled)),
                ("overflowed_tets", u64::from(counts.overflowed)),
                ("unbinned_tets", u64::from(counts.unbinned)),
                // The lists keep the last binned frame's entries through per-tet frames.
                (
                    "bin_entries",
                    u64::from(counts.bin_entries) * u64::from(binned),
                ),
            ]
            .into(),
            ..FrameStats::default()
        };
        if self.path == Path::Compute {
            self.stats.details.insert("binned", u64::from(binned));
        }
        Ok(FrameOutcome::Done)
    }

    fn stats(&self) -> FrameStats {
        self.stats.clone()
    }

    fn counters(&self) -> WorkCounters {
        self.counters
    }

    fn accumulated(&self, gpu: &Gpu) -> Result<Option<Accumulation>> {
        let (Some(pipelines), Some(accumulation)) = (&self.pipelines, &self.accumulation) else {
            return Err(no_data(Technique::Interval));
        };
        let quantity = match pipelines.integrand() {
            Integrand::TetAbsorption
            | Integrand::Scalar {
                mode: ScalarMode::Absorption,
                ..
            } => AccumulatedQuantity::OpticalDepth,
            Integrand::Scalar {
                mode: ScalarMode::Emission,
                ..
            } => AccumulatedQuantity::Emission,
            Integrand::Scalar {
                mode: ScalarMode::Maximum,
                ..
            } => AccumulatedQuantity::Maximum,
            // The compute path keeps packed colours and depth bits there, not floats.
            Integrand::Asteroids => {
                return Err(Error::Invalid(
                    "interval: the asteroid field keeps the nearest hit per pixel, no float \
                     quantity"
                        .into(),
                ))
            }
        };
        Ok(Some(Accumulation {
            width: accumulation.width,
            height: accumulation.height,
            values: accumulation.read(gpu)?,
            quantity,
        }))
    }
}
