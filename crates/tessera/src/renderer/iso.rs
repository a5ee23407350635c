//! Isosurfaces of volumes behind the front door: ray marching, and direct rasterization on its
//! mesh-shader or compute path, with occlusion culling carried from frame to frame.

use super::{
    no_data, wrong_data, Culling, FrameOutcome, FrameStats, Renderer, RendererOptions, Target,
    Technique, WorkCounters,
};
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, DirectCompute, DirectRaster, TriangleLists};
use crate::iso::direct::compute_cull::ComputeCullState;
use crate::iso::direct::cull::CullState;
use crate::iso::direct::cull_choice::{AutoCulling, CullingCosts};
use crate::iso::direct::stereo::DirectMultiview;
use crate::iso::direct::{Direct, RasterTarget};
use crate::iso::raymarch::Raymarch;
use crate::iso::{HiddenSide, PreparedVolume};
use crate::path::{Path, PathChoice};
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{ScalarType, View, Volume};
use tessera_gpu::{Buffer, Gpu, Recorder, Timer};

/// The pipelines of one way to draw the isosurface, built for one sample type.
enum Pipelines {
    Raymarch(Box<Raymarch>),
    Mesh(Box<Direct>),
    Compute(Box<DirectCompute>),
}

/// Buffers of the frame size, made by `prepare_frame`.
enum FrameBuffers {
    None,
    Mesh {
        target: Box<RasterTarget>,
    },
    Compute {
        target: Box<ComputeTarget>,
        culling: Option<Box<ComputeCullState>>,
    },
}

pub(super) struct IsoRenderer {
    technique: Technique,
    path: Path,
    /// The path asked for: under `Auto` a surface too large for the compute path's lists moves
    /// `direct` to the graphics path, which keeps no list, until new data comes.
    path_choice: PathChoice,
    /// The path chosen when the renderer was made, where new data starts.
    chosen_path: Path,
    culling: Culling,
    /// Compute path with automatic culling: whether the next frame culls.
    auto_culling: Option<AutoCulling>,
    /// Whether the last recorded frame was culled.
    last_culled: bool,
    /// How marching cubes cuts ambiguous faces (direct only).
    ambiguity: AmbiguityRule,
    /// Whether `direct` leaves out a closed surface's hidden side (set on each prepared volume).
    hidden_side: HiddenSide,
    /// Where the compute path draws its triangles.
    direct_raster: DirectRaster,
    pipelines: Option<(ScalarType, Pipelines)>,
    prepared: Option<PreparedVolume>,
    /// The isovalue in texel units, and the look it came from (kept to re-resolve against new
    /// data).
    iso: f32,
    look: Appearance,
    value_range: (f32, f32),
    /// Mesh path: culling state of the prepared volume, and the empty triangle capture.
    mesh_culling: Option<CullState>,
    no_capture: Option<Buffer>,
    frame: FrameBuffers,
    /// Compute path: the second eye's lists and raster of a stereo pair.
    second_eye: Option<Box<ComputeTarget>>,
    /// Mesh path with multiview: the stereo pipeline (for the sample type it was built for)
    /// and its two-layer attachments.
    multiview: Option<(ScalarType, Box<DirectMultiview>)>,
    stereo_raster: Option<Box<RasterTarget>>,
    /// Whether the last recording was a stereo pair (drawn without culling).
    stereo: bool,
    /// Mesh path: whether the last recording culled the side of a closed surface no pixel
    /// shows (the compute path's frame says it itself).
    mesh_one_side: bool,
    /// Compute path: triangles a frame's list holds (grown on overflow).
    capacity: u32,
    stats: FrameStats,
    counters: WorkCounters,
}

impl IsoRenderer {
    pub(super) fn new(
        gpu: &Gpu,
        technique: Technique,
        options: &RendererOptions,
    ) -> Result<IsoRenderer> {
        let path = super::path_for(gpu.caps(), technique, options.path)?;
        let culling = match technique {
            Technique::Direct => options.culling,
            _ => Culling::Off,
        };
        Ok(IsoRenderer {
            technique,
            path,
            path_choice: options.path,
            chosen_path: path,
            culling,
            auto_culling: (culling == Culling::Auto && path == Path::Compute)
                .then(|| AutoCulling::new(CullingCosts::H200)),
            last_culled: false,
            ambiguity: options.ambiguity,
            hidden_side: options.hidden_side,
            direct_raster: options.direct_raster,
            pipelines: None,
            prepared: None,
            iso: 0.0,
            look: Appearance::default(),
            value_range: (0.0, 1.0),
            mesh_culling: None,
            no_capture: None,
            frame: FrameBuffers::None,
            second_eye: None,
            multiview: None,
            stereo_raster: None,
            stereo: false,
            mesh_one_side: false,
            // A modest list first; an overflow reports the exact count for the retry.
            capacity: 0,
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }

    fn pipelines_for(&mut self, gpu: &Gpu, scalar: ScalarType) -> Result<&Pipelines> {
        if self.pipelines.as_ref().map(|p| p.0) != Some(scalar) {
            let compiler = crate::shaders::compiler();
            let pipelines = match (self.technique, self.path) {
                (Technique::Raymarch, _) => {
                    Pipelines::Raymarch(Box::new(Raymarch::new(gpu, &compiler, scalar)?))
                }
                (_, Path::Graphics) => Pipelines::Mesh(Box::new(Direct::with_rule(
                    gpu,
                    &compiler,
                    scalar,
                    self.ambiguity,
                )?)),
                (_, Path::Compute) => Pipelines::Compute(Box::new(DirectCompute::with_raster(
                    gpu,
                    &compiler,
                    scalar,
                    self.ambiguity,
                    self.direct_raster,
                )?)),
            };
            self.counters.pipeline_builds += 1;
            self.pipelines = Some((scalar, pipelines));
        }
        Ok(&self.pipelines.as_ref().expect("just built").1)
    }

    /// A compute-path frame made `made` triangles, more than a list on this device holds
    /// (`limit`): with the path left to the renderer and task and mesh shaders at hand, the
    /// frame is drawn again on the graphics path (the prepared volume kept), else an error.
    fn outgrown_lists(&mut self, gpu: &Gpu, made: u32, limit: u32) -> Result<FrameOutcome> {
        let caps = gpu.caps();
        let graphics = caps.mesh_shader && caps.task_shader;
        let prepared = self.prepared.as_ref();
        match (self.path_choice, graphics, &self.pipelines, prepared) {
            (PathChoice::Auto, true, Some((scalar, _)), Some(prepared)) => {
                let scalar = *scalar;
                self.frame = FrameBuffers::None;
                self.second_eye = None;
                self.auto_culling = None;
                self.mesh_culling = match self.culling.enabled() {
                    true => Some(CullState::new(gpu, prepared)?),
                    false => None,
                };
                if self.no_capture.is_none() {
                    self.no_capture = Some(Direct::no_capture(gpu)?);
                }
                self.path = Path::Graphics;
                self.pipelines = None;
                self.pipelines_for(gpu, scalar)?;
                Ok(FrameOutcome::Retry)
            }
            (_, graphics, _, _) => Err(Error::Invalid(format!(
                "the isosurface has {made} triangles, more than the compute path's triangle list \
                 holds on this device ({limit}: a share of its memory, within its largest storage \
                 buffer){}",
                if graphics {
                    "; the graphics path (task and mesh shaders) keeps no list"
                } else {
                    ""
                }
            ))),
        }
    }

    fn resolve_iso(&mut self, volume: Option<&Volume>) -> Result<()> {
        if let Some(volume) = volume {
            self.value_range = volume.texel_range();
        }
        self.iso = self.look.iso_in_range(self.value_range)?;
        Ok(())
    }
}

/// The pipelines and the volume, or the error for a frame asked for before any data.
fn loaded<'a>(
    technique: Technique,
    pipelines: &'a Option<(ScalarType, Pipelines)>,
    prepared: &'a Option<PreparedVolume>,
) -> Result<(&'a Pipelines, &'a PreparedVolume)> {
    match (pipelines, prepared) {
        (Some((_, p)), Some(v)) => Ok((p, v)),
        _ => Err(no_data(technique)),
    }
}

impl Renderer for IsoRenderer {
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
        // The old volume's buffers go before the new one is uploaded.
        self.prepared = None;
        self.mesh_culling = None;
        self.frame = FrameBuffers::None;
        if self.path != self.chosen_path {
            // An earlier surface moved direct off the compute path; new data starts afresh.
            self.second_eye = None;
            self.path = self.chosen_path;
            self.pipelines = None;
            self.auto_culling = (self.culling == Culling::Auto && self.path == Path::Compute)
                .then(|| AutoCulling::new(CullingCosts::H200));
        }
        let mut prepared = match self.pipelines_for(gpu, volume.scalar_type())? {
            Pipelines::Raymarch(r) => r.prepare(gpu, volume)?,
            Pipelines::Mesh(d) => d.prepare(gpu, volume)?,
            Pipelines::Compute(d) => d.prepare(gpu, volume)?,
        };
        prepared.hidden_side = self.hidden_side;
        if matches!(self.pipelines, Some((_, Pipelines::Mesh(_)))) {
            if self.culling.enabled() {
                self.mesh_culling = Some(CullState::new(gpu, &prepared)?);
            }
            if self.no_capture.is_none() {
                self.no_capture = Some(Direct::no_capture(gpu)?);
            }
        }
        self.prepared = Some(prepared);
        if let Some(auto) = &mut self.auto_culling {
            auto.reset();
        }
        self.counters.data_uploads += 1;
        self.counters.data_bytes += volume.size_bytes();
        self.resolve_iso(Some(volume))
    }

    fn set_appearance(&mut self, _gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.look = look.clone();
        if let Some(auto) = &mut self.auto_culling {
            auto.reset();
        }
        self.resolve_iso(None)
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        let (w, h) = view.size;
        let (pipelines, prepared) = loaded(self.technique, &self.pipelines, &self.prepared)?;
        match pipelines {
            Pipelines::Raymarch(_) => {}
            Pipelines::Mesh(_) => {
                let fits = matches!(&self.frame, FrameBuffers::Mesh { target } if (target.width, target.height) == (w, h));
                if !fits {
                    self.frame = FrameBuffers::None;
                    self.frame = FrameBuffers::Mesh {
                        target: Box::new(RasterTarget::new(gpu, w, h)?),
                    };
                }
            }
            Pipelines::Compute(_) => {
                if self.capacity == 0 {
                    self.capacity = TriangleLists::default_capacity(gpu).min(1 << 20);
                }
                let fits = matches!(&self.frame, FrameBuffers::Compute { target, .. }
                    if (target.frame.width, target.frame.height) == (w, h)
                        && target.lists.capacity == self.capacity);
                if !fits {
                    self.frame = FrameBuffers::None;
                    let target = Box::new(ComputeTarget::new(gpu, w, h, self.capacity)?);
                    let culling = if self.culling.enabled() {
                        Some(Box::new(ComputeCullState::new(gpu, prepared, &target)?))
                    } else {
                        None
                    };
                    // A new culling state has no visible set yet: probe afresh.
                    if let Some(auto) = &mut self.auto_culling {
                        auto.reset();
                    }
                    self.frame = FrameBuffers::Compute { target, culling };
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
        self.stereo = false;
        let (pipelines, prepared) = loaded(self.technique, &self.pipelines, &self.prepared)?;
        match (pipelines, &self.frame) {
            (Pipelines::Raymarch(r), _) => {
                let params = Raymarch::params_for_view(prepared, self.iso, view);
                timer.scope(rec, "raymarch", |rec| {
                    r.record(rec, prepared, target, &params)
                });
                Ok(())
            }
            (Pipelines::Mesh(d), FrameBuffers::Mesh { target: raster }) => {
                let params = Direct::params_for_view(prepared, self.iso, view, 0);
                self.mesh_one_side = Direct::hidden_winding(prepared, &params).is_some();
                let capture = self.no_capture.as_ref().expect("made with the data");
                let recorded = timer.scope(rec, "direct", |rec| {
                    d.record(
                        rec,
                        prepared,
                        raster,
                        &params,
                        capture,
                        self.mesh_culling.as_ref(),
                    )
                });
                // Into the shared packed-pixel target, outside the timed frame (a copy of 4
                // bytes per pixel that every presenter needs anyway).
                raster.record_copy_to(rec, target);
                recorded
            }
            (
                Pipelines::Compute(d),
                FrameBuffers::Compute {
                    target: frame,
                    culling,
                },
            ) => {
                let params =
                    Direct::params_for_view(prepared, self.iso, view, frame.lists.capacity);
                let auto = self.auto_culling.as_ref();
                let cull = auto.is_none_or(AutoCulling::cull_next);
                let recorded = match culling.as_ref().filter(|_| cull) {
                    // Frames of the automatic choice are timed whole, culled or not, so that
                    // their timer scopes do not change from frame to frame.
                    Some(state) if auto.is_some() => timer.scope(rec, "direct", |rec| {
                        d.record_culled(rec, prepared, frame, target, &params, state, None)
                    }),
                    // Its passes are timed one by one (first pass, occlusion test, second
                    // pass, resolve).
                    Some(state) => {
                        d.record_culled(rec, prepared, frame, target, &params, state, Some(timer))
                    }
                    None => {
                        timer.scope(rec, "direct", |rec| {
                            d.record(rec, prepared, frame, target, &params)
                        });
                        Ok(())
                    }
                };
                self.last_culled = cull && culling.is_some();
                recorded
            }
            _ => Err(Error::Invalid(format!(
                "{}: record before prepare_frame",
                self.technique.name()
            ))),
        }
    }

    /// The compute path extracts once and re-projects the world-space triangles for the
    /// second eye; the mesh path draws both eyes in one multiview pass where the device has
    /// multiview mesh shaders (paper D §4.1.3). Pairs are drawn without occlusion culling (its
    /// state follows one eye).
    fn prepare_stereo(&mut self, gpu: &Gpu, eyes: &[View; 2]) -> Result<bool> {
        let scalar = match &self.pipelines {
            Some((scalar, Pipelines::Compute(_))) => *scalar,
            Some((scalar, Pipelines::Mesh(_)))
                if gpu.caps().mesh_multiview && eyes[0].size == eyes[1].size =>
            {
                *scalar
            }
            _ => return Ok(false),
        };
        self.prepare_frame(gpu, &eyes[0])?;
        let (w, h) = eyes[1].size;
        if matches!(self.pipelines, Some((_, Pipelines::Mesh(_)))) {
            if self.multiview.as_ref().map(|m| m.0) != Some(scalar) {
                let compiler = crate::shaders::compiler();
                let pipeline = DirectMultiview::with_rule(gpu, &compiler, scalar, self.ambiguity)?;
                self.counters.pipeline_builds += 1;
                self.multiview = Some((scalar, Box::new(pipeline)));
            }
            let fits = self
                .stereo_raster
                .as_ref()
                .is_some_and(|t| (t.width, t.height) == (w, h));
            if !fits {
                self.stereo_raster = None;
                self.stereo_raster = Some(Box::new(RasterTarget::with_views(gpu, w, h, 2)?));
            }
            return Ok(true);
        }
        let fits = self.second_eye.as_ref().is_some_and(|t| {
            (t.frame.width, t.frame.height) == (w, h) && t.lists.capacity == self.capacity
        });
        if !fits {
            self.second_eye = None;
            self.second_eye = Some(Box::new(ComputeTarget::new(gpu, w, h, self.capacity)?));
        }
        Ok(true)
    }

    fn record_stereo(
        &mut self,
        rec: &Recorder,
        eyes: &[View; 2],
        targets: [&Target; 2],
        timer: &mut Timer,
    ) -> Result<()> {
        self.stereo = true;
        let (pipelines, prepared) = loaded(self.technique, &self.pipelines, &self.prepared)?;
        let before_prepare = || {
            Error::Invalid(format!(
                "{}: record_stereo before prepare_stereo",
                self.technique.name()
            ))
        };
        match (pipelines, &self.frame) {
            (Pipelines::Compute(d), FrameBuffers::Compute { target: first, .. }) => {
                let second = self.second_eye.as_ref().ok_or_else(before_prepare)?;
                let capacity = first.lists.capacity;
                let params =
                    eyes.map(|eye| Direct::params_for_view(prepared, self.iso, &eye, capacity));
                timer.scope(rec, "direct-compute-stereo", |rec| {
                    d.record(rec, prepared, first, targets[0], &params[0]);
                    rec.barrier();
                    d.record_second_view(
                        rec,
                        prepared,
                        (first, &params[0]),
                        second,
                        targets[1],
                        &params[1],
                    );
                });
                Ok(())
            }
            (Pipelines::Mesh(d), _) => {
                let (Some((_, multiview)), Some(raster)) = (&self.multiview, &self.stereo_raster)
                else {
                    return Err(before_prepare());
                };
                let params = eyes.map(|eye| Direct::params_for_view(prepared, self.iso, &eye, 0));
                self.mesh_one_side = Direct::pair_hidden_winding(prepared, &params).is_some();
                let capture = self.no_capture.as_ref().expect("made with the data");
                let recorded = timer.scope(rec, "direct-multiview", |rec| {
                    multiview.record(rec, d, prepared, raster, &params, capture)
                });
                // Each layer into its eye's target, outside the timed pass (as mono frames).
                for (layer, target) in targets.into_iter().enumerate() {
                    raster.record_layer_copy_to(rec, layer as u32, target);
                }
                recorded
            }
            _ => Err(before_prepare()),
        }
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let Some((_, pipelines)) = &self.pipelines else {
            return Err(no_data(self.technique));
        };
        self.stats = FrameStats::default();
        match (pipelines, &self.frame) {
            (Pipelines::Raymarch(_), _) => {}
            (Pipelines::Mesh(d), _) => {
                let s = d.read_stats(gpu)?;
                self.stats.triangles = Some(u64::from(s.triangles));
                let details = [
                    ("mesh_workgroups", u64::from(s.mesh_workgroups)),
                    ("one_side_drawn", u64::from(self.mesh_one_side)),
                ];
                self.stats.details.extend(details);
                if let Some(state) = self.mesh_culling.as_ref().filter(|_| !self.stereo) {
                    let s = state.read_stats(gpu)?;
                    self.stats.blocks_drawn = Some((
                        u64::from(s.blocks_drawn_first),
                        u64::from(s.blocks_drawn_new),
                    ));
                    let details = [
                        ("regions_occupied", s.regions_occupied),
                        ("blocks_visible", s.blocks_visible),
                    ];
                    self.stats
                        .details
                        .extend(details.map(|(k, v)| (k, u64::from(v))));
                }
            }
            (Pipelines::Compute(d), FrameBuffers::Compute { target, culling }) => {
                let capacity = target.lists.capacity;
                let pixels = u64::from(target.frame.width) * u64::from(target.frame.height);
                // Each of a culled frame's two lists holds `capacity` triangles.
                let made = match culling
                    .as_ref()
                    .filter(|_| !self.stereo && self.last_culled)
                {
                    Some(state) => {
                        let s = state.read_stats();
                        if let Some(auto) = &mut self.auto_culling {
                            auto.after_culled(s.blocks_drawn(), s.blocks_occupied, pixels);
                        }
                        self.stats.blocks_drawn = Some((
                            u64::from(s.blocks_drawn_first),
                            u64::from(s.blocks_drawn_new),
                        ));
                        self.stats.triangles = Some(u64::from(s.triangles()));
                        let details = [
                            ("triangles_first_pass", s.triangles_first),
                            ("triangles_second_pass", s.triangles_new),
                            ("triangles_second_pass_hidden", s.triangles_new_hidden),
                            ("blocks_occupied", s.blocks_occupied),
                            ("blocks_visible", s.blocks_visible),
                        ];
                        self.stats
                            .details
                            .extend(details.map(|(k, v)| (k, u64::from(v))));
                        s.triangles_first.max(s.triangles_new)
                    }
                    None => {
                        let s = d.read_stats(gpu)?;
                        if let Some(auto) = self.auto_culling.as_mut().filter(|_| !self.stereo) {
                            auto.after_unculled();
                        }
                        self.stats.triangles = Some(u64::from(s.triangles));
                        self.stats
                            .details
                            .insert("blocks_classified", u64::from(s.blocks_classified));
                        s.triangles
                    }
                };
                if culling.is_some() && !self.stereo {
                    self.stats
                        .details
                        .insert("culled", u64::from(self.last_culled));
                }
                let one_side = target.frame.hidden_winding().is_some();
                self.stats
                    .details
                    .insert("one_side_drawn", u64::from(one_side));
                if made > capacity {
                    let limit = TriangleLists::default_capacity(gpu);
                    if made > limit {
                        return self.outgrown_lists(gpu, made, limit);
                    }
                    // Headroom, so that the next frames of a moving camera or isovalue
                    // rarely overflow again.
                    self.capacity = made.saturating_add(made / 4 + 1024).min(limit);
                    return Ok(FrameOutcome::Retry);
                }
            }
            (Pipelines::Compute(_), _) => {}
        }
        Ok(FrameOutcome::Done)
    }

    fn stats(&self) -> FrameStats {
        self.stats.clone()
    }

    fn counters(&self) -> WorkCounters {
        self.counters
    }
}
