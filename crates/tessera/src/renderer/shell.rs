//! Tet meshes behind the front door by shell traversal (paper B): emission–absorption of the
//! vertex scalars through the look's transfer function, with the options' secondary-ray
//! effects (shadows and a ground plane, ambient occlusion, gradient shading). The layout and
//! the effects are compiled into the pipelines; a new transfer function, density or scalar
//! range is a table write and a push constant.

use super::{
    no_data, wrong_data, AccumulatedQuantity, Accumulation, FrameOutcome, FrameStats, Renderer,
    RendererOptions, Target, Technique, WorkCounters,
};
use crate::error::{Error, Result};
use crate::path::Path;
use crate::tet::shell::{
    EffectBuffers, EffectParams, GpuShellMesh, RadianceBuffer, Shell, ShellOptions,
};
use glam::DVec3;
use tessera_data::scene::{Appearance, DataKind, Dataset, TetData};
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::scalar_integral::mapping_range;
use tessera_data::tet::shell::{LayoutKind, ShellEffects, ShellMesh};
use tessera_data::View;
use tessera_gpu::{Gpu, Recorder, Timer};

struct MeshOnGpu {
    data: TetData,
    mesh: GpuShellMesh,
    /// World-space bounds, which place the ground plane.
    bounds: (DVec3, DVec3),
    /// The effects' buffers (with effects only).
    effects: Option<EffectBuffers>,
    /// The effect settings the per-tet lighting in `effects` was computed with; `None` until
    /// a frame lit the tets for the current mesh and look (the lighting depends on them and
    /// on the light, not on the eye, so frames after that reuse it).
    lit_with: Option<EffectParams>,
    /// The settings of the frame recorded last, lit by it when it completes.
    lighting_recorded: Option<EffectParams>,
}

pub(super) struct ShellRenderer {
    /// The graphics path is the ray-tracing pipeline.
    path: Path,
    layout: LayoutKind,
    effects: ShellEffects,
    data: Option<MeshOnGpu>,
    look: Appearance,
    optics: Option<EmissionAbsorption>,
    pass: Option<Shell>,
    background: [f32; 3],
    /// The float radiance behind the colours, at the last prepared size.
    radiance: Option<RadianceBuffer>,
    stats: FrameStats,
    counters: WorkCounters,
}

impl ShellRenderer {
    pub(super) fn new(gpu: &Gpu, options: &RendererOptions) -> Result<ShellRenderer> {
        Ok(ShellRenderer {
            path: super::path_for(gpu.caps(), Technique::Shell, options.path)?,
            layout: options.layout,
            effects: options.shell_effects(),
            data: None,
            look: Appearance::default(),
            optics: None,
            pass: None,
            background: [0.0; 3],
            radiance: None,
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }

    /// The optical model and scalar range of the look for the mesh; builds the pipeline the
    /// first time, else writes the tables.
    fn apply_look(&mut self, gpu: &Gpu) -> Result<()> {
        let Some(data) = &mut self.data else {
            return Ok(());
        };
        if !(self.look.density.is_finite() && self.look.density > 0.0) {
            return Err(Error::Invalid(format!(
                "--density must be a positive number, not {}",
                self.look.density
            )));
        }
        data.mesh.scalar_range = mapping_range(&data.data.mesh, self.look.range, &data.data.name)?;
        data.lit_with = None;
        let optics = EmissionAbsorption::new(&self.look.transfer, self.look.density);
        match &self.pass {
            Some(pass) => pass.set_optics(gpu, &optics)?,
            None => {
                let options = ShellOptions::on(self.layout, self.path);
                let compiler = crate::shaders::compiler();
                let pass = Shell::with_effects(gpu, &compiler, &options, &optics, &self.effects)?;
                self.pass = Some(pass);
                self.counters.pipeline_builds += 1;
            }
        }
        self.optics = Some(optics);
        self.background = self.look.background(DataKind::Tets, None);
        Ok(())
    }
}

impl Renderer for ShellRenderer {
    fn technique(&self) -> Technique {
        Technique::Shell
    }

    fn path(&self) -> Path {
        self.path
    }

    fn set_data(&mut self, gpu: &Gpu, data: &Dataset) -> Result<()> {
        let Dataset::Tets(tets) = data else {
            return Err(wrong_data(Technique::Shell, data));
        };
        if tets.asteroids {
            return Err(Error::Invalid(format!(
                "{}: shell traversal integrates vertex scalars; draw asteroid fields with interval",
                tets.name
            )));
        }
        self.data = None;
        let shell = ShellMesh::build(&tets.mesh)?;
        let mesh = GpuShellMesh::upload_for(gpu, &shell, self.layout, self.path)?;
        self.counters.data_uploads += 1;
        self.counters.data_bytes += mesh.bytes();
        // The mesh as loaded names the scalars' range; the reordered copy is on the GPU.
        let effects = if self.effects.any() {
            Some(EffectBuffers::new(gpu, &shell, &self.effects, 0)?)
        } else {
            None
        };
        self.data = Some(MeshOnGpu {
            data: tets.clone(),
            mesh,
            bounds: shell.world_bounds(),
            effects,
            lit_with: None,
            lighting_recorded: None,
        });
        self.apply_look(gpu)
    }

    fn set_appearance(&mut self, gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.look = look.clone();
        self.apply_look(gpu)
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        let (Some(_), Some(data)) = (&self.pass, &mut self.data) else {
            return Err(no_data(Technique::Shell));
        };
        if let Some(buffers) = &mut data.effects {
            buffers.resize(gpu, u64::from(view.size.0) * u64::from(view.size.1))?;
        }
        let (width, height) = view.size;
        if !matches!(&self.radiance, Some(r) if (r.width, r.height) == (width, height)) {
            self.radiance = Some(RadianceBuffer::new(gpu, width, height)?);
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
        let (Some(pass), Some(data), Some(radiance)) = (&self.pass, &mut self.data, &self.radiance)
        else {
            return Err(no_data(Technique::Shell));
        };
        let params = pass.params(&data.mesh, view, self.background);
        match (&data.effects, &self.optics) {
            (Some(buffers), Some(optics)) => {
                let effect = EffectParams::new(&self.effects, view, data.bounds, optics);
                let relight = data.lit_with != Some(effect);
                data.lighting_recorded = relight.then_some(effect);
                pass.record_effects(
                    rec,
                    &data.mesh,
                    buffers,
                    (target, radiance),
                    &params,
                    &effect,
                    relight,
                    timer,
                )
            }
            _ => timer.scope(rec, "shell traversal", |rec| {
                pass.record(rec, &data.mesh, target, radiance, &params)
            }),
        }
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let pass = self
            .pass
            .as_ref()
            .ok_or_else(|| no_data(Technique::Shell))?;
        if let Some(data) = &mut self.data {
            if let Some(lit) = data.lighting_recorded.take() {
                data.lit_with = Some(lit);
            }
        }
        let s = pass.read_stats(gpu)?;
        let mut details: std::collections::BTreeMap<&'static str, u64> = [
            ("segments", s.segments),
            ("tet_steps", s.steps),
            ("guard_dead_ends", s.dead_ends),
            ("guard_step_limits", s.step_limits),
            ("unmatched_exits", s.unmatched_exits),
        ]
        .into();
        if self.effects.any() {
            let secondary = pass.read_secondary(gpu)?;
            details.extend([
                ("shadow_rays", secondary.shadow_rays),
                ("ao_rays", secondary.ao_rays),
                ("secondary_steps", secondary.steps),
                ("secondary_guard_hits", secondary.guard_hits),
            ]);
        }
        self.stats = FrameStats {
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

    fn accumulated(&self, gpu: &Gpu) -> Result<Option<Accumulation>> {
        let radiance = self
            .radiance
            .as_ref()
            .ok_or_else(|| no_data(Technique::Shell))?;
        Ok(Some(Accumulation {
            width: radiance.width,
            height: radiance.height,
            values: radiance.read(gpu)?,
            quantity: AccumulatedQuantity::Radiance,
        }))
    }
}
