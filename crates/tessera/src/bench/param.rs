//! Parametric-object benchmark scenarios (paper E §5): one SH glyph of orders 2…12, and a
//! 140 × 140 field of order-12 glyphs at several distances (Figures 8–10), at 1920×1080 with and
//! without 2×2 supersampling, by the point and the tessellation variants and by ray tracing
//! (Peters et al.); 24,000 order-8 glyphs at 1280×720; a knitted curtain of 59,690 yarn curves and a seashell (§5.3); the LOD
//! stage and the drawing timed apart. `--paths` picks the techniques by the path they take:
//! tessellation the graphics path, points and ray tracing compute.

use super::{time_frames, BenchRecord, FramePlan};
use super::{BenchConfig, RecordSink};
use crate::error::{Error, Result};
use crate::path::Path;
use crate::renderer::{self, RendererOptions, Target, Technique, MAX_TIMER_SCOPES};
use tessera_data::scene::{Dataset, LoadOptions};
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

pub fn param(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let size = if config.quick {
        (320, 180)
    } else {
        (1920, 1080)
    };
    let load = |spec: &str| Dataset::load(spec, &LoadOptions::default());
    let wanted = |techniques: &[Technique]| -> Vec<Technique> {
        techniques
            .iter()
            .copied()
            .filter(|&t| config.paths.is_empty() || config.paths.contains(&path_of(t)))
            .collect()
    };
    let all = wanted(ALL);
    let orders: &[u32] = if config.quick {
        &[2, 8]
    } else {
        &[2, 4, 6, 8, 10, 12]
    };
    for &order in orders {
        let spec = format!("param:sh-glyph:order{order}");
        let scene = load(&spec)?;
        let camera = OrbitCamera {
            distance: 3.0,
            ..OrbitCamera::default()
        };
        measure(gpu, &scene, &[("single", camera)], &all, size, plan, sink)?;
    }
    let grid = if config.quick { "20x20" } else { "140x140" };
    let spec = format!("param:sh-glyphs:{grid}:order12");
    let scene = load(&spec)?;
    let at = |distance: f32| OrbitCamera {
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        distance,
        ..OrbitCamera::default()
    };
    let views = [("far", at(1.2)), ("mid", at(0.5)), ("close", at(0.15))];
    measure(gpu, &scene, &views, &all, size, plan, sink)?;
    // 24,000 order-8 glyphs at 1280×720: the size a DIPY viewer's billboard glyphs are
    // reported at (474 frames a second, 2.1 ms).
    let (field, small) = if config.quick {
        ("param:sh-glyphs:16x15:order8", (160, 90))
    } else {
        ("param:sh-glyphs:160x150:order8", (1280, 720))
    };
    measure(gpu, &load(field)?, &views, &all, small, plan, sink)?;
    // Paper E §5.3: a knitted curtain of 235 × 254 loops (59,690 yarn curves), and a seashell.
    let shapes = wanted(&[Technique::ParamPoints, Technique::ParamTess]);
    let yarn = if config.quick {
        "param:yarn:10x10"
    } else {
        "param:yarn:235x254"
    };
    let views = [("whole", at(1.3)), ("close", at(0.3))];
    measure(gpu, &load(yarn)?, &views, &shapes, size, plan, sink)?;
    let views = [(
        "whole",
        OrbitCamera {
            distance: 2.0,
            ..OrbitCamera::default()
        },
    )];
    measure(
        gpu,
        &load("param:seashell")?,
        &views,
        &shapes,
        size,
        plan,
        sink,
    )
}

/// The path a parametric technique takes.
fn path_of(technique: Technique) -> Path {
    match technique {
        Technique::ParamTess => Path::Graphics,
        _ => Path::Compute,
    }
}

/// Every parametric technique; ray tracing draws SH glyphs only.
const ALL: &[Technique] = &[
    Technique::ParamPoints,
    Technique::ParamTess,
    Technique::ShRaytrace,
];

fn measure(
    gpu: &Gpu,
    data: &Dataset,
    views: &[(&str, OrbitCamera)],
    techniques: &[Technique],
    size: (u32, u32),
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let Dataset::Param(param) = data else {
        return Err(Error::Invalid(format!(
            "{}: not a parametric scene",
            data.name()
        )));
    };
    let target = Target::new(gpu, size.0, size.1)?;
    for &technique in techniques {
        for supersample in [1, 2] {
            let options = RendererOptions {
                supersample,
                ..RendererOptions::default()
            };
            let mut renderer = renderer::create(gpu, technique, &options)?;
            renderer.set_data(gpu, data)?;
            views.iter().try_for_each(|(view_name, camera)| {
                let view = renderer.view(camera, size)?;
                renderer.prepare_frame(gpu, &view)?;
                let mut recorded = Ok(());
                let stages = time_frames(gpu, plan, MAX_TIMER_SCOPES, |rec, timer| {
                    if let Err(e) = renderer.record(rec, &view, &target, timer) {
                        recorded = Err(e);
                    }
                });
                recorded?;
                renderer.finish_frame(gpu)?;
                let patches = renderer.stats().patches.unwrap_or(0);
                let dataset = format!("{}, {view_name}", param.name);
                // Records name the tessellation variant's pipeline as the papers do.
                let path = match technique {
                    Technique::ParamTess => "tessellation",
                    _ => renderer.path().name(),
                };
                let mut r = BenchRecord::new(gpu, "param", technique.name(), path, &dataset);
                r.variant = format!("{supersample}x{supersample} samples per pixel");
                (r.width, r.height, r.warmup, r.frames, r.stages) =
                    (size.0, size.1, plan.warmup, plan.frames, stages?);
                r.counts
                    .insert("objects".into(), param.scene.objects.len() as f64);
                r.counts.insert("patches".into(), patches as f64);
                // Every scope but the LOD stage draws, however many the technique takes.
                let lod = r.median_ms("lod").unwrap_or(0.0);
                let draw: f64 = (r.stages.iter())
                    .filter(|s| s.stage != "lod")
                    .map(|s| s.median_ms)
                    .sum();
                if lod + draw > 0.0 {
                    r.counts.insert("lod_share".into(), lod / (lod + draw));
                }
                sink.emit(&r)
            })?;
        }
    }
    Ok(())
}
