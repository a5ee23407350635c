//! The parametric techniques behind one type, so that `render` and `bench` drive them alike:
//! the point and tessellation variants of paper E and the ray-traced SH glyphs they are
//! compared with.

use anyhow::{bail, Result};
use tessera::param::raytrace::{RaytraceScene, ShRaytrace, ShRaytraceOptions};
use tessera::param::scene::{GpuParamScene, ParamScene};
use tessera::param::tess::{ParamTess, ParamTessOptions, TessFrame};
use tessera::param::{ParamPoints, ParamPointsOptions, PointsFrame, View};
use tessera::target::Target;
use tessera_data::OrbitCamera;
use tessera_gpu::{Gpu, Recorder, ShaderCompiler, Timer};

pub enum ParamRenderer {
    Points(ParamPoints),
    Tess(ParamTess),
    Raytrace(ShRaytrace),
}

/// A scene on the GPU as its technique needs it.
pub enum PreparedScene {
    Plain(Box<GpuParamScene>),
    Raytrace(Box<RaytraceScene>),
}

/// A frame of the matching technique.
pub enum ParamFrame {
    Points(Box<PointsFrame>),
    Tess(Box<TessFrame>),
    Pixels(Target),
}

impl ParamRenderer {
    /// `technique`: param-points, param-tess or sh-raytrace; `msaa` applies to param-tess only,
    /// `pre_split` (k × k patches per object to start from) to the two patch techniques.
    pub fn new(
        gpu: &Gpu,
        compiler: &ShaderCompiler,
        technique: &str,
        supersample: u32,
        msaa: u32,
        pre_split: u32,
    ) -> Result<ParamRenderer> {
        if msaa != 1 && technique != "param-tess" {
            bail!("--msaa applies to param-tess; {technique} supersamples instead");
        }
        Ok(match technique {
            "param-tess" => ParamRenderer::Tess(ParamTess::new(
                gpu,
                compiler,
                ParamTessOptions {
                    supersample,
                    msaa,
                    pre_split,
                    ..ParamTessOptions::default()
                },
            )?),
            "sh-raytrace" => ParamRenderer::Raytrace(ShRaytrace::new(
                gpu,
                compiler,
                ShRaytraceOptions {
                    supersample,
                    ..ShRaytraceOptions::default()
                },
            )?),
            _ => ParamRenderer::Points(ParamPoints::new(
                gpu,
                compiler,
                ParamPointsOptions {
                    supersample,
                    pre_split,
                    ..ParamPointsOptions::default()
                },
            )?),
        })
    }

    pub fn name(&self) -> &'static str {
        match self {
            ParamRenderer::Points(_) => "param-points",
            ParamRenderer::Tess(_) => "param-tess",
            ParamRenderer::Raytrace(_) => "sh-raytrace",
        }
    }

    /// The pipeline kind, for benchmark records.
    pub fn path(&self) -> &'static str {
        match self {
            ParamRenderer::Tess(_) => "tessellation",
            _ => "compute",
        }
    }

    pub fn prepare(&self, gpu: &Gpu, scene: &ParamScene) -> Result<PreparedScene> {
        Ok(match self {
            ParamRenderer::Raytrace(r) => PreparedScene::Raytrace(Box::new(r.prepare(gpu, scene)?)),
            _ => PreparedScene::Plain(Box::new(GpuParamScene::upload(gpu, scene)?)),
        })
    }

    pub fn view(
        &self,
        scene: &PreparedScene,
        camera: &OrbitCamera,
        size: (u32, u32),
    ) -> Result<View> {
        Ok(match (self, scene) {
            (ParamRenderer::Points(p), PreparedScene::Plain(s)) => p.view(s, camera, size)?,
            (ParamRenderer::Tess(t), PreparedScene::Plain(s)) => t.view(s, camera, size)?,
            (ParamRenderer::Raytrace(r), PreparedScene::Raytrace(s)) => r.view(s, camera, size)?,
            _ => unreachable!("scenes come from their renderer's `prepare`"),
        })
    }

    pub fn frame(&self, gpu: &Gpu, view: &View, size: (u32, u32)) -> Result<ParamFrame> {
        Ok(match self {
            ParamRenderer::Points(_) => ParamFrame::Points(Box::new(PointsFrame::new(gpu, view)?)),
            ParamRenderer::Tess(t) => ParamFrame::Tess(Box::new(t.frame(gpu, view)?)),
            ParamRenderer::Raytrace(_) => ParamFrame::Pixels(Target::new(gpu, size.0, size.1)?),
        })
    }

    /// Records a frame with the LOD stage (none for ray tracing) and the drawing in timer
    /// scopes "lod" and "draw".
    pub fn record_timed(
        &self,
        rec: &Recorder,
        timer: &mut Timer,
        scene: &PreparedScene,
        view: &View,
        frame: &ParamFrame,
        background: [f32; 3],
    ) {
        match (self, scene, frame) {
            (ParamRenderer::Points(p), PreparedScene::Plain(s), ParamFrame::Points(f)) => {
                p.record_timed(rec, timer, s, view, f, background)
            }
            (ParamRenderer::Tess(t), PreparedScene::Plain(s), ParamFrame::Tess(f)) => {
                t.record_timed(rec, timer, s, view, f, background)
            }
            (ParamRenderer::Raytrace(r), PreparedScene::Raytrace(s), ParamFrame::Pixels(f)) => {
                timer.scope(rec, "draw", |rec| r.record(rec, s, view, f, background))
            }
            _ => unreachable!("scenes and frames come from their renderer"),
        }
    }

    /// Patches the LOD stage handed to the drawing in one untimed frame (0 for ray tracing).
    pub fn patches(
        &self,
        gpu: &Gpu,
        scene: &PreparedScene,
        view: &View,
        frame: &ParamFrame,
        background: [f32; 3],
    ) -> Result<u32> {
        let info = match (self, scene, frame) {
            (ParamRenderer::Points(p), PreparedScene::Plain(s), ParamFrame::Points(f)) => {
                p.render_frame(gpu, s, view, f, background)?
            }
            (ParamRenderer::Tess(t), PreparedScene::Plain(s), ParamFrame::Tess(f)) => {
                t.render_frame(gpu, s, view, f, background)?
            }
            _ => return Ok(0),
        };
        Ok(info.stats.rendered)
    }
}
