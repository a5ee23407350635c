//! Parametric-object benchmark scenarios (paper E §5): one SH glyph of orders 2…12, and a
//! 140 × 140 field of order-12 glyphs at several distances (Figures 8–10), at 1920×1080 with and
//! without 2×2 supersampling, by the point and the tessellation variants and by ray tracing
//! (Peters et al.); a knitted curtain of 59,690 yarn curves and a seashell (§5.3); the LOD
//! stage and the drawing timed apart.

use crate::bench::{BenchArgs, Sink};
use crate::param_renderer::ParamRenderer;
use anyhow::Result;
use tessera::bench::{time_frames, BenchRecord, FramePlan};
use tessera::param::scene::ParamScene;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

pub fn param(gpu: &Gpu, args: &BenchArgs, plan: FramePlan, sink: &mut Sink) -> Result<()> {
    let compiler = tessera::shaders::compiler();
    let size = if args.quick { (320, 180) } else { (1920, 1080) };
    let basis = tessera_data::scene::param_spec::default_basis("");
    let orders: &[u32] = if args.quick {
        &[2, 8]
    } else {
        &[2, 4, 6, 8, 10, 12]
    };
    for &order in orders {
        let spec = format!("param:sh-glyph:order{order}");
        let scene = tessera_data::scene::param_spec::named_scene(&spec, basis)?;
        let camera = OrbitCamera {
            distance: 3.0,
            ..OrbitCamera::default()
        };
        measure(
            gpu,
            &compiler,
            &scene,
            &spec,
            &[("single", camera)],
            ALL,
            size,
            plan,
            sink,
        )?;
    }
    let grid = if args.quick { "20x20" } else { "140x140" };
    let spec = format!("param:sh-glyphs:{grid}:order12");
    let scene = tessera_data::scene::param_spec::named_scene(&spec, basis)?;
    let at = |distance: f32| OrbitCamera {
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        distance,
        ..OrbitCamera::default()
    };
    let views = [("far", at(1.2)), ("mid", at(0.5)), ("close", at(0.15))];
    measure(gpu, &compiler, &scene, &spec, &views, ALL, size, plan, sink)?;
    // Paper E §5.3: a knitted curtain of 235 × 254 loops (59,690 yarn curves), and a seashell.
    let shapes = ["param-points", "param-tess"];
    let yarn = if args.quick {
        "param:yarn:10x10"
    } else {
        "param:yarn:235x254"
    };
    let scene = tessera_data::scene::param_spec::named_scene(yarn, basis)?;
    let views = [("whole", at(1.3)), ("close", at(0.3))];
    measure(
        gpu, &compiler, &scene, yarn, &views, &shapes, size, plan, sink,
    )?;
    let scene = tessera_data::scene::param_spec::named_scene("param:seashell", basis)?;
    let views = [(
        "whole",
        OrbitCamera {
            distance: 2.0,
            ..OrbitCamera::default()
        },
    )];
    measure(
        gpu,
        &compiler,
        &scene,
        "param:seashell",
        &views,
        &shapes,
        size,
        plan,
        sink,
    )
}

/// Every parametric technique; ray tracing draws SH glyphs only.
const ALL: &[&str] = &["param-points", "param-tess", "sh-raytrace"];

#[allow(clippy::too_many_arguments)]
fn measure(
    gpu: &Gpu,
    compiler: &tessera_gpu::ShaderCompiler,
    scene: &ParamScene,
    name: &str,
    views: &[(&str, OrbitCamera)],
    techniques: &[&str],
    size: (u32, u32),
    plan: FramePlan,
    sink: &mut Sink,
) -> Result<()> {
    for &technique in techniques {
        for supersample in [1, 2] {
            let renderer = ParamRenderer::new(gpu, compiler, technique, supersample, 1, 1)?;
            let gpu_scene = renderer.prepare(gpu, scene)?;
            views.iter().try_for_each(|(view_name, camera)| {
                let view = renderer.view(&gpu_scene, camera, size)?;
                let frame = renderer.frame(gpu, &view, size)?;
                let background = [0.1, 0.1, 0.12];
                let stages = time_frames(gpu, plan, 2, |rec, timer| {
                    renderer.record_timed(rec, timer, &gpu_scene, &view, &frame, background)
                });
                let patches = renderer.patches(gpu, &gpu_scene, &view, &frame, background)?;
                let dataset = format!("{name}, {view_name}");
                let path = renderer.path();
                let mut r = BenchRecord::new(gpu, "param", renderer.name(), path, &dataset);
                r.variant = format!("{supersample}x{supersample} samples per pixel");
                (r.width, r.height, r.warmup, r.frames, r.stages) =
                    (size.0, size.1, plan.warmup, plan.frames, stages?);
                r.counts
                    .insert("objects".into(), scene.objects.len() as f64);
                r.counts.insert("patches".into(), f64::from(patches));
                let lod = r.median_ms("lod").unwrap_or(0.0);
                let draw = r.median_ms("draw").unwrap_or(0.0);
                if lod + draw > 0.0 {
                    r.counts.insert("lod_share".into(), lod / (lod + draw));
                }
                sink.emit(&r)
            })?;
        }
    }
    Ok(())
}
