//! Isosurface benchmark scenarios that set techniques side by side in one run, every one
//! driven through the front door.

use super::basic::{bench_sizes, bench_volumes, make_volume};
use super::frames::{settle_after_upload, time_mono, EachFrame};
use super::raster_ablation::direct_ablations;
use super::{time_frames, BenchRecord, FramePlan};
use super::{BenchConfig, RecordSink};
use crate::error::{Error, Result};
use crate::iso::direct::compute::{ComputeTarget, DirectCompute};
use crate::iso::direct::{Direct, RasterTarget};
use crate::iso::minmax::upload_samples;
use crate::iso::raymarch::Raymarch;
use crate::iso::PreparedVolume;
use crate::path::{Path, PathChoice};
use crate::renderer::{
    self, Culling, DirectRaster, HiddenSide, Renderer, RendererOptions, Technique,
};
use crate::target::Target;
use std::collections::BTreeMap;
use tessera_data::pmb::PmbBlockSize;
use tessera_data::scene::{Appearance, Dataset};
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};
use tessera_gpu::{Gpu, ShaderCompiler};

/// Each frame's isovalue as a fraction of the value range; `None` keeps it fixed.
type Sweep<'a> = Option<&'a dyn Fn(u32) -> f32>;

/// Frames with distinct isovalues in a sweep's period: the settling renders each once.
const SWEEP_PERIOD: u32 = 64;

/// One way of drawing the isosurface, as the records name it.
pub(super) struct IsoTechnique {
    pub(super) technique: Technique,
    pub(super) options: RendererOptions,
    /// The record's technique and path names.
    pub(super) name: &'static str,
    pub(super) path: &'static str,
    /// The record's variant (PMB's block size), empty for none.
    pub(super) variant: String,
}

/// Ray marching, then `direct` on each path the device has, without and with culling (and on
/// the compute path with culling where it pays).
pub(super) fn iso_techniques(gpu: &Gpu, sink: &mut dyn RecordSink) -> Vec<IsoTechnique> {
    let with = |path, culling| RendererOptions {
        path,
        culling,
        ..RendererOptions::default()
    };
    let mut out = vec![IsoTechnique {
        technique: Technique::Raymarch,
        options: with(PathChoice::Compute, Culling::Off),
        name: "raymarch",
        path: "compute",
        variant: String::new(),
    }];
    let caps = gpu.caps();
    if caps.mesh_shader && caps.task_shader {
        for (culling, name) in [(Culling::Off, "direct"), (Culling::On, "direct+roc")] {
            out.push(IsoTechnique {
                technique: Technique::Direct,
                options: with(PathChoice::Graphics, culling),
                name,
                path: "mesh",
                variant: String::new(),
            });
        }
    } else {
        sink.note(&format!(
            "{} has no task/mesh shaders; direct is skipped",
            caps.device_name
        ));
    }
    if caps.buffer_int64_atomics {
        let choices = [
            (Culling::Off, "direct"),
            (Culling::On, "direct+hzb"),
            (Culling::Auto, "direct+auto"),
        ];
        for (culling, name) in choices {
            out.push(IsoTechnique {
                technique: Technique::Direct,
                options: with(PathChoice::Compute, culling),
                name,
                path: "compute",
                variant: String::new(),
            });
        }
    } else {
        sink.note(&format!(
            "{} has no 64-bit buffer atomics; direct's compute path is skipped",
            caps.device_name
        ));
    }
    out
}

/// Paper C's persistent meshlets, extracted on the GPU per isovalue (`meshlets`) or built
/// offline by meshoptimizer from the CPU mesh (`offline`, drawn only), and its real-time
/// reference PMB (each block size, extracted per isovalue), on each path the device has;
/// frustum-culled by their boxes.
pub(super) fn meshlet_techniques(gpu: &Gpu) -> Vec<IsoTechnique> {
    let caps = gpu.caps();
    let pmb = crate::iso::pmb_draw::path_support(caps);
    let techniques = [
        (Technique::Meshlets, "meshlets"),
        (Technique::Offline, "offline"),
        (Technique::Pmb, "pmb"),
    ];
    let mut out = Vec::new();
    for (technique, name) in techniques {
        let paths = match technique {
            Technique::Pmb => [
                (PathChoice::Graphics, "graphics", pmb.graphics),
                (PathChoice::Compute, "compute", pmb.compute),
            ],
            _ => [
                (
                    PathChoice::Graphics,
                    "mesh",
                    caps.mesh_shader && caps.task_shader,
                ),
                (PathChoice::Compute, "compute", caps.buffer_int64_atomics),
            ],
        };
        let block_sizes: Vec<Option<PmbBlockSize>> = match technique {
            Technique::Pmb => PmbBlockSize::ALL.map(Some).to_vec(),
            _ => vec![None],
        };
        for (path, path_name, available) in paths {
            for &block in block_sizes.iter().filter(|_| available) {
                out.push(IsoTechnique {
                    technique,
                    options: RendererOptions {
                        path,
                        pmb_block: block.unwrap_or_default(),
                        ..RendererOptions::default()
                    },
                    name,
                    path: path_name,
                    variant: block.map(PmbBlockSize::name).unwrap_or_default(),
                });
            }
        }
    }
    out
}

/// A variant of the isosurface scenarios (`--variants NAME`): each draw it applies to is timed
/// again with one option changed, right after itself.
struct IsoVariant {
    name: &'static str,
    /// Added to the twin's record variant.
    label: &'static str,
    applies: fn(&IsoTechnique) -> bool,
    change: fn(&mut RendererOptions),
}

const ISO_VARIANTS: [IsoVariant; 2] = [
    IsoVariant {
        name: "hidden-side",
        label: "hidden side drawn",
        // The stored surfaces' graphics draws draw both sides whatever the option says.
        applies: |t| {
            t.technique.reads_options().contains(&"hidden_side")
                && (t.path == "compute" || t.technique == Technique::Direct)
        },
        change: |o| o.hidden_side = HiddenSide::Draw,
    },
    IsoVariant {
        name: "raster-in-extraction",
        label: "raster in extraction",
        applies: |t| t.technique == Technique::Direct && t.path == "compute",
        change: |o| o.direct_raster = DirectRaster::InExtraction,
    },
];

/// `techniques`, each followed by its twin where the variant `variants` names applies.
fn with_variants(
    techniques: Vec<IsoTechnique>,
    variants: Option<&str>,
) -> Result<Vec<IsoTechnique>> {
    let Some(wanted) = variants else {
        return Ok(techniques);
    };
    let Some(variant) = ISO_VARIANTS.iter().find(|v| v.name == wanted) else {
        let names: Vec<_> = ISO_VARIANTS
            .iter()
            .map(|v| format!("'{}'", v.name))
            .collect();
        return Err(Error::Invalid(format!(
            "the isosurface scenarios' variants are {}, not '{wanted}'",
            names.join(" and ")
        )));
    };
    let mut out = Vec::with_capacity(2 * techniques.len());
    for t in techniques {
        let twin = (variant.applies)(&t).then(|| {
            let mut options = t.options;
            (variant.change)(&mut options);
            IsoTechnique {
                technique: t.technique,
                options,
                name: t.name,
                path: t.path,
                variant: [t.variant.as_str(), variant.label]
                    .iter()
                    .filter(|v| !v.is_empty())
                    .copied()
                    .collect::<Vec<_>>()
                    .join(", "),
            }
        });
        out.push(t);
        out.extend(twin);
    }
    Ok(out)
}

/// Ray marching and the techniques named in `wanted` (all where it is empty); a name that none
/// of `techniques` (this device's, on the paths asked for) bears is refused.
fn chosen(techniques: Vec<IsoTechnique>, wanted: &[String]) -> Result<Vec<IsoTechnique>> {
    if let Some(unknown) = wanted
        .iter()
        .find(|w| !techniques.iter().any(|t| t.name == w.as_str()))
    {
        let mut names: Vec<&str> = Vec::new();
        for t in &techniques {
            if !names.contains(&t.name) {
                names.push(t.name);
            }
        }
        return Err(Error::Invalid(format!(
            "no isosurface technique '{unknown}' here; there are {}",
            names.join(", ")
        )));
    }
    Ok(techniques
        .into_iter()
        .filter(|t| {
            t.technique == Technique::Raymarch
                || wanted.is_empty()
                || wanted.iter().any(|w| w == t.name)
        })
        .collect())
}

/// The look of frame `k`: the scenario's isovalue, or the sweep's.
fn look_of(config: &BenchConfig, sweep: Sweep, k: u32) -> Appearance {
    let fraction = sweep.map_or(config.iso_fraction, |f| f(k));
    Appearance {
        iso: IsoValue::Normalized(fraction),
        ..Appearance::default()
    }
}

/// A renderer of `t` holding `data`, settled after the upload.
pub(super) fn iso_renderer(
    gpu: &Gpu,
    t: &IsoTechnique,
    data: &Dataset,
    look: &Appearance,
    config: &BenchConfig,
) -> Result<Box<dyn Renderer>> {
    let mut r = renderer::create(gpu, t.technique, &t.options)?;
    r.set_appearance(gpu, look)?;
    r.set_data(gpu, data)?;
    settle_after_upload(gpu, r.as_mut(), config.quick)?;
    Ok(r)
}

fn run_scenario(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
    scenario: &str,
    sweep: Sweep,
) -> Result<()> {
    let camera = OrbitCamera::default();
    let mut techniques = iso_techniques(gpu, sink);
    techniques.extend(meshlet_techniques(gpu));
    // Ray marching, the reference every speed-up counts against, runs whatever the paths.
    techniques.retain(|t| {
        let path = match t.options.path {
            PathChoice::Graphics => Path::Graphics,
            _ => Path::Compute,
        };
        t.technique == Technique::Raymarch
            || config.paths.is_empty()
            || config.paths.contains(&path)
    });
    let techniques = with_variants(
        chosen(techniques, &config.techniques)?,
        config.variants.as_deref(),
    )?;
    for spec in bench_volumes(config) {
        let data = Dataset::Volume(make_volume(gpu, &spec, config)?);
        let volume_name = data.name().to_string();
        // Ray marching's median per image size, for the speed-ups.
        let mut raymarch_ms: BTreeMap<(u32, u32), f64> = BTreeMap::new();
        for t in &techniques {
            // Offline meshlets are built on the CPU per isovalue: not a per-frame technique.
            if sweep.is_some() && t.technique == Technique::Offline {
                continue;
            }
            let mut r = iso_renderer(gpu, t, &data, &look_of(config, sweep, 0), config)?;
            let each_frame =
                |k: u32, r: &mut dyn Renderer| r.set_appearance(gpu, &look_of(config, sweep, k));
            let each: EachFrame =
                sweep.map(|_| &each_frame as &dyn Fn(u32, &mut dyn Renderer) -> Result<()>);
            let distinct = if sweep.is_some() { SWEEP_PERIOD } else { 1 };
            for size in bench_sizes(config) {
                let view = r.view(&camera, size)?;
                let stages = time_mono(gpu, r.as_mut(), &view, plan, distinct, each)?;
                let mut record = BenchRecord::new(gpu, scenario, t.name, t.path, &volume_name);
                record.variant = t.variant.clone();
                (record.width, record.height, record.warmup, record.frames) =
                    (size.0, size.1, plan.warmup, plan.frames);
                record.stages = stages;
                record.add_frame_stats(&r.stats());
                match (t.technique, record.frame_ms()) {
                    (Technique::Raymarch, Some(ms)) => {
                        raymarch_ms.insert(size, ms);
                    }
                    (_, Some(ms)) => {
                        if let Some(rm) = raymarch_ms.get(&size) {
                            record
                                .counts
                                .insert("speedup_over_raymarch".into(), rm / ms);
                        }
                    }
                    _ => {}
                }
                sink.emit(&record)?;
            }
        }
        if config.ablations && sweep.is_none() {
            if let Dataset::Volume(volume) = &data {
                direct_ablations(gpu, config, plan, sink, volume, &volume_name)?;
            }
        }
    }
    Ok(())
}

/// `raymarch` against `direct` on the same volumes, sizes and camera; with
/// `config.ablations` also where `direct`'s compute frame spends its time
/// (`raster_ablation`).
pub fn isosurface(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    run_scenario(gpu, config, plan, sink, "isosurface", None)
}

/// The isovalue moves every frame, from 20 % to 60 % of the value range and back, as when a
/// user drags a slider: nothing may be precomputed per isovalue.
pub fn iso_sweep(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let sweep = move |frame: u32| {
        let phase = (frame % SWEEP_PERIOD) as f32 / SWEEP_PERIOD as f32;
        0.2 + 0.4 * (1.0 - (2.0 * phase - 1.0).abs())
    };
    run_scenario(gpu, config, plan, sink, "iso-sweep", Some(&sweep))
}

/// The pipelines of the time-varying scenario, which streams volume steps into one upload:
/// something the front door has no call for yet, so it drives the techniques directly.
struct Techniques {
    raymarch: Raymarch,
    direct: Option<Direct>,
    direct_compute: Option<DirectCompute>,
}

fn techniques(gpu: &Gpu, compiler: &ShaderCompiler, scalar: ScalarType) -> Result<Techniques> {
    let caps = gpu.caps();
    Ok(Techniques {
        raymarch: Raymarch::new(gpu, compiler, scalar)?,
        direct: (caps.mesh_shader && caps.task_shader)
            .then(|| Direct::new(gpu, compiler, scalar))
            .transpose()?,
        direct_compute: caps
            .buffer_int64_atomics
            .then(|| DirectCompute::new(gpu, compiler, scalar))
            .transpose()?,
    })
}

/// A new volume every frame, as when playing back a simulation's time steps: each frame copies
/// the next step from host memory into the volume texture, rebuilds the octree and renders.
/// The steps are the four procedural fields at one size and type, staged in host memory.
pub fn time_varying(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    use tessera_data::procedural::{generate, ProceduralKind};
    let compiler = crate::shaders::compiler();
    let sizes: &[(u32, ScalarType)] = if config.quick {
        &[(48, ScalarType::U8)]
    } else {
        &[(256, ScalarType::U8), (512, ScalarType::U8)]
    };
    let camera = OrbitCamera::default();
    for &(size, scalar) in sizes {
        let kinds = [
            ProceduralKind::HeadPhantom,
            ProceduralKind::Turbulence,
            ProceduralKind::MarschnerLobb,
            ProceduralKind::Sphere,
        ];
        let steps: Vec<Volume> = kinds
            .iter()
            .map(|&k| generate(k, size, scalar))
            .collect::<std::result::Result<_, _>>()?;
        let staged: Vec<_> = steps
            .iter()
            .map(|v| gpu.staging_with(v.name(), v.bytes()))
            .collect::<std::result::Result<_, _>>()?;
        let dims = steps[0].dims();
        // Each step is a different volume: the warm-up judges whole cycles through them.
        let plan = FramePlan {
            frames_per_cycle: steps.len() as u32,
            ..plan
        };
        let resident: Vec<_> = steps
            .iter()
            .map(|v| upload_samples(gpu, v, tessera_gpu::vk::BufferUsageFlags::TRANSFER_SRC))
            .collect::<Result<_>>()?;
        let isos: Vec<f32> = steps
            .iter()
            .map(|v| v.iso_to_texel(IsoValue::Normalized(config.iso_fraction)))
            .collect();
        let t = techniques(gpu, &compiler, scalar)?;
        let builder = crate::iso::minmax::MinMaxBuilder::new(gpu, &compiler, scalar)?;
        let mut prepared = PreparedVolume::new(gpu, &builder, &steps[0])?;
        // The steps are copied into its samples in turn: the boundary of all of them.
        prepared.boundary_range = steps
            .iter()
            .map(tessera_data::facing::boundary_range)
            .fold(prepared.boundary_range, |a, b| (a.0.min(b.0), a.1.max(b.1)));
        // Each frame copies the next time step in and rebuilds the octree; returns its index.
        let next_step =
            |rec: &tessera_gpu::Recorder, timer: &mut tessera_gpu::Timer, frame: &mut usize| {
                let k = *frame % steps.len();
                *frame += 1;
                timer.scope(rec, "upload", |rec| {
                    rec.copy_buffer_to_image(&staged[k], &prepared.volume.texture)
                });
                rec.barrier();
                timer.scope(rec, "octree-build", |rec| {
                    builder.record(rec, &prepared.volume, &prepared.octree)
                });
                rec.barrier();
                k
            };
        let dataset = format!("{size}^3 {} x{} steps", scalar.name(), steps.len());
        for (w, h) in bench_sizes(config) {
            let mut frame = 0usize;
            let target = Target::new(gpu, w, h)?;
            let stages = time_frames(gpu, plan, 3, |rec, timer| {
                let k = next_step(rec, timer, &mut frame);
                let params = Raymarch::params(&prepared, isos[k], &camera, w, h);
                timer.scope(rec, "raymarch", |rec| {
                    t.raymarch.record(rec, &prepared, &target, &params)
                });
            })?;
            let mut r = BenchRecord::new(gpu, "time-varying", "raymarch", "compute", &dataset);
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages);
            r.counts
                .insert("step_bytes".into(), steps[0].size_bytes() as f64);
            sink.emit(&r)?;
            // The same playback with the steps held on the GPU (a time series that fits its
            // memory): each frame copies the step into the texture and builds the octree from
            // the step's buffer, whose rows read in whole cache lines.
            let mut recorded = Ok(());
            let stages = time_frames(gpu, plan, 3, |rec, timer| {
                let k = frame % steps.len();
                frame += 1;
                timer.scope(rec, "upload", |rec| {
                    rec.copy_buffer_to_image(&resident[k], &prepared.volume.texture)
                });
                rec.barrier();
                let built = timer.scope(rec, "octree-build", |rec| {
                    builder.record_from_samples(rec, &resident[k], dims, &prepared.octree)
                });
                if recorded.is_ok() {
                    recorded = built;
                }
                rec.barrier();
                let params = Raymarch::params(&prepared, isos[k], &camera, w, h);
                timer.scope(rec, "raymarch", |rec| {
                    t.raymarch.record(rec, &prepared, &target, &params)
                });
            })?;
            recorded?;
            drop(target);
            let mut r = BenchRecord::new(gpu, "time-varying", "raymarch", "compute", &dataset);
            r.variant = "steps on the GPU".into();
            (r.width, r.height, r.warmup, r.frames, r.stages) =
                (w, h, plan.warmup, plan.frames, stages);
            r.counts
                .insert("step_bytes".into(), steps[0].size_bytes() as f64);
            sink.emit(&r)?;
            if let Some(direct) = &t.direct {
                let target = RasterTarget::new(gpu, w, h)?;
                let capture = Direct::no_capture(gpu)?;
                let mut recorded = Ok(());
                let stages = time_frames(gpu, plan, 3, |rec, timer| {
                    let k = next_step(rec, timer, &mut frame);
                    let params = Direct::params(&prepared, isos[k], &camera, w, h, 0);
                    let result = timer.scope(rec, "direct", |rec| {
                        direct.record(rec, &prepared, &target, &params, &capture, None)
                    });
                    recorded = recorded.clone().and(result.map_err(|e| e.to_string()));
                });
                recorded.map_err(Error::Invalid)?;
                let mut r = BenchRecord::new(gpu, "time-varying", "direct", "mesh", &dataset);
                (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
                r.stages = stages?;
                r.counts
                    .insert("step_bytes".into(), steps[0].size_bytes() as f64);
                sink.emit(&r)?;
            }
            if let Some(compute) = &t.direct_compute {
                // Lists sized for the largest step's isosurface.
                let mut most = 0u32;
                let probe = ComputeTarget::new(gpu, 1, 1, 1)?;
                let probe_pixels = Target::new(gpu, 1, 1)?;
                for (k, step) in staged.iter().enumerate() {
                    let params = Direct::params(&prepared, isos[k], &camera, 1, 1, 1);
                    gpu.submit("count triangles", |rec| {
                        rec.copy_buffer_to_image(step, &prepared.volume.texture);
                        rec.barrier();
                        builder.record(rec, &prepared.volume, &prepared.octree);
                        rec.barrier();
                        compute.record(rec, &prepared, &probe, &probe_pixels, &params);
                    })?;
                    most = most.max(compute.read_stats(gpu)?.triangles);
                }
                drop((probe, probe_pixels));
                let capacity = most + most / 8 + 1024;
                let target = ComputeTarget::new(gpu, w, h, capacity)?;
                let pixels = Target::new(gpu, w, h)?;
                let stages = time_frames(gpu, plan, 3, |rec, timer| {
                    let k = next_step(rec, timer, &mut frame);
                    let params = Direct::params(&prepared, isos[k], &camera, w, h, capacity);
                    timer.scope(rec, "direct", |rec| {
                        compute.record(rec, &prepared, &target, &pixels, &params)
                    });
                });
                let mut r = BenchRecord::new(gpu, "time-varying", "direct", "compute", &dataset);
                (r.width, r.height, r.warmup, r.frames) = (w, h, plan.warmup, plan.frames);
                r.stages = stages?;
                r.counts
                    .insert("step_bytes".into(), steps[0].size_bytes() as f64);
                sink.emit(&r)?;
            }
        }
    }
    Ok(())
}
