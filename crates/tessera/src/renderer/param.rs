//! Parametric objects behind the front door (paper E): the patch LOD stage drawn by points or
//! by hardware tessellation, and SH glyphs ray-traced as their reference. A user's GLSL
//! function is compiled into the pipelines, so they are built with the data.

use super::{
    no_data, wrong_data, FrameOutcome, FrameStats, Renderer, RendererOptions, Target, Technique,
    WorkCounters,
};
use crate::error::{Error, Result};
use crate::param::raytrace::{RaytraceScene, ShRaytrace, ShRaytraceOptions};
use crate::param::scene::GpuParamScene;
use crate::param::tess::{ParamTess, ParamTessOptions, TessFrame};
use crate::param::user::register_user_function;
use crate::param::{ParamPoints, ParamPointsOptions, PointsFrame};
use crate::path::Path;
use tessera_data::param::user::UserFunction;
use tessera_data::param::ParamFunction;
use tessera_data::scene::{Appearance, DataKind, Dataset};
use tessera_data::{DepthFit, View};
use tessera_gpu::{Gpu, Recorder, Timer};

enum Pipelines {
    Points(Box<ParamPoints>),
    Tess(Box<ParamTess>),
    Raytrace(Box<ShRaytrace>),
}

/// The scene on the GPU as the technique needs it.
enum SceneOnGpu {
    Plain(Box<GpuParamScene>),
    Raytrace(Box<RaytraceScene>),
}

impl SceneOnGpu {
    fn bounds(&self) -> &[(glam::Vec3, f32)] {
        match self {
            SceneOnGpu::Plain(s) => &s.bounds,
            SceneOnGpu::Raytrace(s) => &s.scene.bounds,
        }
    }
}

enum FrameBuffers {
    Points(Box<PointsFrame>),
    Tess(Box<TessFrame>),
}

pub(super) struct ParamRenderer {
    technique: Technique,
    /// Tessellation runs on the graphics stages; points and ray tracing on compute.
    path: Path,
    options: RendererOptions,
    /// Built with the first data set, for its user function (`None`: the built-in functions
    /// only): a user function is compiled into every pass, and building twice would cost the
    /// compile twice.
    pipelines: Option<(Option<UserFunction>, Pipelines)>,
    /// Each object starts as `pre_split`² patches: the option, else chosen with the data.
    pre_split: u32,
    /// Patches each LOD list holds: raised to hold a scene's initial patches, and grown when a
    /// frame overflows (the pipelines are then built again).
    patch_capacity: u32,
    scene: Option<SceneOnGpu>,
    background: [f32; 3],
    frame: Option<((u32, u32), FrameBuffers)>,
    stats: FrameStats,
    counters: WorkCounters,
}

impl ParamRenderer {
    pub(super) fn new(
        gpu: &Gpu,
        technique: Technique,
        options: &RendererOptions,
    ) -> Result<ParamRenderer> {
        if options.msaa != 1 && technique != Technique::ParamTess {
            return Err(Error::Invalid(format!(
                "msaa (multisampling) applies to param-tess; {} supersamples instead",
                technique.name()
            )));
        }
        // The one device feature a variant needs, checked before any data is loaded.
        if technique == Technique::ParamPoints && !gpu.caps().buffer_int64_atomics {
            return Err(Error::Invalid(format!(
                "param-points needs 64-bit buffer atomics, which {} lacks",
                gpu.caps().device_name
            )));
        }
        Ok(ParamRenderer {
            technique,
            path: super::path_for(gpu.caps(), technique, options.path)?,
            options: *options,
            pipelines: None,
            pre_split: options.pre_split.unwrap_or(1),
            patch_capacity: ParamPointsOptions::default().patch_capacity,
            scene: None,
            background: Appearance::default().background(DataKind::Param, None),
            frame: None,
            stats: FrameStats::default(),
            counters: WorkCounters::default(),
        })
    }

    fn build(&mut self, gpu: &Gpu, user: Option<&UserFunction>) -> Result<()> {
        let same = |a: Option<&UserFunction>| {
            a.map(|f| (&f.name, &f.text)) == user.map(|f| (&f.name, &f.text))
        };
        let (capacity, pre_split) = (self.patch_capacity, self.pre_split);
        let built_with = |p: &Pipelines| match p {
            Pipelines::Points(p) => (p.options().patch_capacity, p.options().pre_split),
            Pipelines::Tess(t) => (t.options().patch_capacity, t.options().pre_split),
            Pipelines::Raytrace(_) => (capacity, pre_split),
        };
        if self
            .pipelines
            .as_ref()
            .is_some_and(|(u, p)| same(u.as_ref()) && built_with(p) == (capacity, pre_split))
        {
            return Ok(());
        }
        self.pipelines = None;
        self.frame = None;
        let mut compiler = crate::shaders::compiler();
        if let Some(f) = user {
            register_user_function(f, &mut compiler)?;
        }
        let o = &self.options;
        let pipelines = match self.technique {
            Technique::ParamTess => Pipelines::Tess(Box::new(ParamTess::new(
                gpu,
                &compiler,
                ParamTessOptions {
                    supersample: o.supersample,
                    msaa: o.msaa,
                    pre_split,
                    patch_capacity: capacity,
                    ..ParamTessOptions::default()
                },
            )?)),
            Technique::ShRaytrace => Pipelines::Raytrace(Box::new(ShRaytrace::new(
                gpu,
                &compiler,
                ShRaytraceOptions {
                    supersample: o.supersample,
                    ..ShRaytraceOptions::default()
                },
            )?)),
            _ => Pipelines::Points(Box::new(ParamPoints::new(
                gpu,
                &compiler,
                ParamPointsOptions {
                    supersample: o.supersample,
                    pre_split,
                    patch_capacity: capacity,
                    ..ParamPointsOptions::default()
                },
            )?)),
        };
        self.counters.pipeline_builds += 1;
        self.pipelines = Some((user.cloned(), pipelines));
        Ok(())
    }

    /// The CPU cannot evaluate a user's GLSL: its extent is measured on the GPU, by the point
    /// variant's probe (built for the purpose when this renderer is another variant).
    fn measure_user_bounds(
        &self,
        gpu: &Gpu,
        f: &UserFunction,
        scene: &mut GpuParamScene,
    ) -> Result<()> {
        match &self.pipelines {
            Some((_, Pipelines::Points(points))) => {
                crate::param::user::measure_bounds(f, gpu, points, scene, 0)
            }
            _ => {
                let mut compiler = crate::shaders::compiler();
                register_user_function(f, &mut compiler)?;
                let probe = ParamPoints::new(gpu, &compiler, ParamPointsOptions::default())?;
                crate::param::user::measure_bounds(f, gpu, &probe, scene, 0)
            }
        }
    }
}

impl Renderer for ParamRenderer {
    fn technique(&self) -> Technique {
        self.technique
    }

    fn path(&self) -> Path {
        self.path
    }

    fn set_data(&mut self, gpu: &Gpu, data: &Dataset) -> Result<()> {
        let Dataset::Param(param) = data else {
            return Err(wrong_data(self.technique, data));
        };
        self.scene = None;
        let has_glyphs = param
            .scene
            .objects
            .iter()
            .any(|o| matches!(o.function, ParamFunction::ShGlyph(_)));
        self.pre_split = self.options.pre_split.unwrap_or(
            if self.technique == Technique::ParamTess && has_glyphs {
                TESS_GLYPH_PRE_SPLIT
            } else {
                1
            },
        );
        // The first LOD list holds every object's initial patches, with headroom for splits.
        let split = self.pre_split;
        let initial = param.scene.objects.len() as u64 * u64::from(split * split);
        let wanted = (initial + initial / 4).min(u64::from(patch_capacity_limit(gpu))) as u32;
        self.patch_capacity = self.patch_capacity.max(wanted);
        self.build(gpu, param.user.as_ref())?;
        let scene = match &self.pipelines {
            Some((_, Pipelines::Raytrace(r))) => {
                SceneOnGpu::Raytrace(Box::new(r.prepare(gpu, &param.scene)?))
            }
            _ => {
                let mut uploaded = GpuParamScene::upload(gpu, &param.scene)?;
                if let Some(f) = &param.user {
                    self.measure_user_bounds(gpu, f, &mut uploaded)?;
                }
                SceneOnGpu::Plain(Box::new(uploaded))
            }
        };
        self.counters.data_uploads += 1;
        self.counters.data_bytes += match &scene {
            SceneOnGpu::Plain(s) => s.bytes(),
            SceneOnGpu::Raytrace(s) => s.bytes(),
        };
        self.scene = Some(scene);
        Ok(())
    }

    fn set_appearance(&mut self, _gpu: &Gpu, look: &Appearance) -> Result<()> {
        self.background = look.background(DataKind::Param, None);
        Ok(())
    }

    fn depth_fit(&self) -> DepthFit<'_> {
        match &self.scene {
            Some(scene) => DepthFit::Spheres(scene.bounds()),
            None => DepthFit::UnitBox,
        }
    }

    fn supersample(&self) -> u32 {
        self.options.supersample
    }

    fn prepare_frame(&mut self, gpu: &Gpu, view: &View) -> Result<()> {
        let Some((_, pipelines)) = &self.pipelines else {
            return Err(no_data(self.technique));
        };
        if self
            .frame
            .as_ref()
            .is_some_and(|(size, _)| *size == view.raster_size())
        {
            return Ok(());
        }
        self.frame = None;
        let buffers = match pipelines {
            Pipelines::Points(_) => FrameBuffers::Points(Box::new(PointsFrame::new(gpu, view)?)),
            Pipelines::Tess(t) => FrameBuffers::Tess(Box::new(t.frame(gpu, view)?)),
            Pipelines::Raytrace(_) => return Ok(()),
        };
        self.frame = Some((view.raster_size(), buffers));
        Ok(())
    }

    fn record(
        &mut self,
        rec: &Recorder,
        view: &View,
        target: &Target,
        timer: &mut Timer,
    ) -> Result<()> {
        let (Some((_, pipelines)), Some(scene)) = (&self.pipelines, &self.scene) else {
            return Err(no_data(self.technique));
        };
        let frame = self.frame.as_ref().map(|f| &f.1);
        match (pipelines, scene, frame) {
            (Pipelines::Points(p), SceneOnGpu::Plain(s), Some(FrameBuffers::Points(f))) => {
                p.record_timed(rec, timer, s, view, f, target, self.background);
            }
            (Pipelines::Tess(t), SceneOnGpu::Plain(s), Some(FrameBuffers::Tess(f))) => {
                t.record_timed(rec, timer, s, view, f, target, self.background);
            }
            (Pipelines::Raytrace(r), SceneOnGpu::Raytrace(s), _) => {
                r.check_scene(s)?;
                timer.scope(rec, "draw", |rec| {
                    r.record(rec, s, view, target, self.background)
                });
            }
            _ => {
                return Err(Error::Invalid(format!(
                    "{}: record before prepare_frame",
                    self.technique.name()
                )))
            }
        }
        Ok(())
    }

    fn finish_frame(&mut self, gpu: &Gpu) -> Result<FrameOutcome> {
        let lod = match &self.pipelines {
            Some((_, Pipelines::Points(p))) => {
                Some((p.read_lod_stats(gpu)?, p.options().patch_capacity))
            }
            Some((_, Pipelines::Tess(t))) => {
                Some((t.read_lod_stats(gpu)?, t.options().patch_capacity))
            }
            _ => None,
        };
        self.stats = FrameStats::default();
        if let Some((stats, capacity)) = lod {
            if stats.dropped > 0 {
                let limit = patch_capacity_limit(gpu);
                if capacity >= limit {
                    return Err(Error::Invalid(format!(
                        "{} lost {} patches to full lists of {capacity}, the most this device \
                         holds: raise the LOD thresholds or lower the pre-split",
                        self.technique.name(),
                        stats.dropped
                    )));
                }
                // Patches lost in one step also hide the children they would have made:
                // at least double.
                let needed = u64::from(capacity) + u64::from(stats.dropped) * 5 / 4;
                self.patch_capacity =
                    needed.max(u64::from(capacity) * 2).min(u64::from(limit)) as u32;
                let user = self.pipelines.take().and_then(|(u, _)| u);
                self.frame = None;
                self.build(gpu, user.as_ref())?;
                return Ok(FrameOutcome::Retry);
            }
            self.stats.patches = Some(u64::from(stats.rendered));
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

/// param-tess's pre-split of scenes with SH glyphs: a patch gets at most 64 segments per edge,
/// which left small order-8 glyphs at a silhouette IoU of 0.977 against ray tracing (0.987 from
/// 2 × 2 patches, 8×8 field at 256²).
const TESS_GLYPH_PRE_SPLIT: u32 = 2;

#[cfg(test)]
#[path = "param_tests.rs"]
mod tests;

/// Most patches a LOD list may hold on `gpu`: three lists within an eighth of its memory,
/// each within one storage-buffer binding and 32-bit byte offsets.
fn patch_capacity_limit(gpu: &Gpu) -> u32 {
    let patch = std::mem::size_of::<crate::param::lod::GpuPatch>() as u64;
    let caps = gpu.caps();
    (caps.device_local_bytes / 8 / (3 * patch))
        .min(caps.max_storage_buffer_range / patch)
        .min(u64::from(u32::MAX) / patch) as u32
}
