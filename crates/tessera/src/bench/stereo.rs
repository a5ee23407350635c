//! The stereo benchmark: a pair of eyes against one, on every isosurface path, through the
//! front door.

use super::basic::{bench_volumes, make_volume};
use super::frames::{time_mono_total, time_stereo, Pair};
use super::iso::{iso_renderer, iso_techniques, IsoTechnique};
use super::{BenchConfig, BenchRecord, FramePlan, RecordSink, StageStats};
use crate::error::Result;
use crate::renderer::{self, Frame, Renderer};
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{IsoValue, OrbitCamera, View};
use tessera_gpu::Gpu;

/// Two eyes against one: how much a stereo pair costs over a single view (paper D §4.1.3).
/// Ray marching traces both eyes with one renderer; the mesh path with occlusion culling draws the eyes one
/// after the other, each with its own culling state; without culling it draws both in one
/// multiview pass where the device can; the compute path extracts once and re-projects for
/// the second eye.
pub fn stereo(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let size = if config.quick {
        (256, 144)
    } else {
        (3840, 2160)
    };
    let separation = 0.06;
    let look = Appearance {
        iso: IsoValue::Normalized(config.iso_fraction),
        ..Appearance::default()
    };
    let techniques = iso_techniques(gpu, sink);
    for spec in bench_volumes(config) {
        let data = Dataset::Volume(make_volume(gpu, &spec, config)?);
        let mut multiview_match = None;
        for t in &techniques {
            // Pairs are drawn without culling (its state follows one eye), except by two
            // renderers, one per eye, for the culled mesh path.
            let mut r = iso_renderer(gpu, t, &data, &look, config)?;
            let mono_view = r.view(&OrbitCamera::default(), size)?;
            let eyes = mono_view.stereo_pair(separation);
            let mono = time_mono_total(gpu, r.as_mut(), &mono_view, plan, "mono")?;
            let (record_name, pair) = if t.options.culling.enabled() {
                if t.path != "mesh" {
                    continue;
                }
                let mut second = iso_renderer(gpu, t, &data, &look, config)?;
                let pair = Pair::TwoFrames([r.as_mut(), second.as_mut()]);
                (t.name, time_stereo(gpu, pair, &eyes, plan, "stereo")?)
            } else if r.prepare_stereo(gpu, &eyes)? {
                let name = match t.path {
                    "mesh" => "direct-multiview",
                    _ => t.name,
                };
                if t.path == "mesh" {
                    multiview_match = Some(layers_match(gpu, r.as_mut(), &eyes)?);
                }
                let pair = time_stereo(gpu, Pair::OnePass(r.as_mut()), &eyes, plan, "stereo")?;
                (name, pair)
            } else if t.path == "mesh" {
                // Without multiview the unculled mesh path adds nothing to the culled one.
                continue;
            } else {
                // Ray marching keeps nothing between frames: one renderer (and one copy of
                // the volume) draws both eyes.
                let pair = Pair::OneRendererTwoFrames(r.as_mut());
                (t.name, time_stereo(gpu, pair, &eyes, plan, "stereo")?)
            };
            emit(
                gpu,
                sink,
                t,
                record_name,
                data.name(),
                size,
                plan,
                mono,
                pair,
                separation,
            )?;
        }
        match multiview_match {
            Some(fraction) => sink.note(&format!(
                "multiview layers match single-eye renders: {fraction:.4} of pixels"
            )),
            None => sink.note(&format!(
                "{} has no multiview mesh shaders",
                gpu.caps().device_name
            )),
        }
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn emit(
    gpu: &Gpu,
    sink: &mut dyn RecordSink,
    t: &IsoTechnique,
    name: &str,
    dataset: &str,
    (w, h): (u32, u32),
    plan: FramePlan,
    mono: StageStats,
    pair: StageStats,
    separation: f32,
) -> Result<()> {
    let mut r = BenchRecord::new(gpu, "stereo", name, t.path, dataset);
    (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
    r.counts
        .insert("stereo_over_mono".into(), pair.median_ms / mono.median_ms);
    r.counts.insert("eye_separation".into(), separation as f64);
    r.stages = vec![mono, pair];
    sink.emit(&r)
}

/// The smallest fraction of pixels (within 2/255) in which a one-pass pair's eyes equal mono
/// frames of the same eyes.
fn layers_match(gpu: &Gpu, r: &mut dyn Renderer, eyes: &[View; 2]) -> Result<f64> {
    let size = eyes[0].size;
    let (mut left, mut right) = (Frame::new(gpu, size)?, Frame::new(gpu, size)?);
    renderer::render_stereo(gpu, r, eyes, &mut left, &mut right)?;
    let mut single = Frame::new(gpu, size)?;
    let mut matches = 1.0f64;
    for (eye, frame) in eyes.iter().zip([&left, &right]) {
        single.render(gpu, r, eye)?;
        let diff = frame
            .target
            .read(gpu)?
            .compare(&single.target.read(gpu)?, 2);
        matches = matches.min(diff.fraction_within);
    }
    r.prepare_stereo(gpu, eyes)?;
    Ok(matches)
}
