//! Cost growth (`growth`): every technique's frame time against the image's pixels (the middle
//! dataset of its family at each of the scenario's image sizes) and against the data's size (a
//! ladder of datasets of its family at one image size), each technique on the path the device
//! would pick for it. Records say which ladder they belong to in `variant` ("pixels" or
//! "data") and carry the data's size as a count ("voxels", "tets" or "glyphs") and "pixels".
//! `--paths` keeps the techniques whose picked path it lists.

use super::frames::{settle_after_upload, time_mono};
use super::{BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::Result;
use crate::renderer::{self, Renderer, RendererOptions, Technique};
use tessera_data::scene::{Appearance, DataKind, Dataset, LoadOptions};
use tessera_data::{IsoValue, OrbitCamera};
use tessera_gpu::Gpu;

/// One family of data: the techniques that draw it and its datasets, smallest first.
struct Ladder {
    techniques: &'static [Technique],
    specs: Vec<String>,
    /// The count that measures a dataset's size.
    unit: &'static str,
}

const VOLUME_TECHNIQUES: &[Technique] = &[
    Technique::Raymarch,
    Technique::Direct,
    Technique::Meshlets,
    Technique::Pmb,
    Technique::Offline,
];

/// Volumes past this many voxels skip `offline`: its meshlets are made on the CPU (marching
/// cubes, then meshoptimizer), minutes for a 1024³ surface, and its draw is what is timed.
const OFFLINE_MAX_VOXELS: f64 = 512.0 * 512.0 * 512.0;
const TET_TECHNIQUES: &[Technique] = &[Technique::Interval, Technique::Shell];
const PARAM_TECHNIQUES: &[Technique] = &[
    Technique::ParamPoints,
    Technique::ParamTess,
    Technique::ShRaytrace,
];

fn ladders(quick: bool) -> Vec<Ladder> {
    let specs = |pattern: &str, sizes: &[&str]| -> Vec<String> {
        sizes.iter().map(|s| pattern.replace("{}", s)).collect()
    };
    let (volumes, boxes, glyphs) = if quick {
        (
            &["24:u8", "40:u8"][..],
            &["2", "3"][..],
            &["2x2", "3x3"][..],
        )
    } else {
        (
            &["128:u8", "256:u8", "512:u8", "1024:u16"][..],
            &["10", "22", "46", "74"][..],
            &["10x10", "35x35", "70x70", "140x140"][..],
        )
    };
    vec![
        Ladder {
            techniques: VOLUME_TECHNIQUES,
            specs: specs("procedural:head:{}", volumes),
            unit: "voxels",
        },
        Ladder {
            techniques: TET_TECHNIQUES,
            specs: specs("tets:box:{}", boxes),
            unit: "tets",
        },
        Ladder {
            techniques: PARAM_TECHNIQUES,
            specs: specs(
                &format!("param:sh-glyphs:{{}}:order{}", if quick { 4 } else { 12 }),
                glyphs,
            ),
            unit: "glyphs",
        },
    ]
}

/// The size of `data` in its ladder's unit.
fn data_size(data: &Dataset) -> f64 {
    match data {
        Dataset::Volume(v) => v.dims().iter().map(|&d| d as f64).product(),
        Dataset::Tets(t) => t.mesh.tets.len() as f64,
        Dataset::Param(p) => p.scene.objects.len() as f64,
    }
}

/// The image sizes of the pixel ladder and the one size of the data ladder (the middle one).
fn image_sizes(config: &BenchConfig) -> (Vec<(u32, u32)>, (u32, u32)) {
    let sizes = if config.quick && config.sizes.is_empty() {
        vec![(128, 72), (256, 144)]
    } else {
        super::basic::bench_sizes(config)
    };
    let middle = sizes[sizes.len() / 2];
    (sizes, middle)
}

pub(super) fn growth(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let (pixel_sizes, data_image) = image_sizes(config);
    for ladder in ladders(config.quick) {
        let middle = ladder.specs.len() / 2;
        for (i, spec) in ladder.specs.iter().enumerate() {
            let data = Dataset::load(spec, &LoadOptions::default())?;
            let cells: Vec<((u32, u32), &str)> = if i == middle {
                let mut cells: Vec<_> = pixel_sizes.iter().map(|&s| (s, "pixels")).collect();
                if !pixel_sizes.contains(&data_image) {
                    cells.push((data_image, "data"));
                }
                cells
            } else {
                vec![(data_image, "data")]
            };
            for &technique in ladder.techniques {
                if technique == Technique::Offline && data_size(&data) > OFFLINE_MAX_VOXELS {
                    sink.note(&format!(
                        "growth: offline skipped on {} (its meshlets are built on the CPU)",
                        data.name()
                    ));
                    continue;
                }
                let mut r = growth_renderer(gpu, technique, &data, config)?;
                if !config.paths.is_empty() && !config.paths.contains(&r.path()) {
                    continue; // `--paths` leaves this technique's path out
                }
                settle_after_upload(gpu, r.as_mut(), config.quick)?;
                for &(size, ladder_name) in &cells {
                    let view = r.view(&OrbitCamera::default(), size)?;
                    let stages = time_mono(gpu, r.as_mut(), &view, plan, 1, None)?;
                    let path = r.path().name();
                    let mut record =
                        BenchRecord::new(gpu, "growth", technique.name(), path, data.name());
                    record.variant = ladder_name.into();
                    (record.width, record.height, record.warmup, record.frames) =
                        (size.0, size.1, plan.warmup, plan.frames);
                    record.stages = stages;
                    record.add_frame_stats(&r.stats());
                    record.counts.insert(ladder.unit.into(), data_size(&data));
                    record
                        .counts
                        .insert("pixels".into(), f64::from(size.0) * f64::from(size.1));
                    sink.emit(&record)?;
                    // The middle dataset at the data ladder's image size is a cell of both.
                    if i == middle && size == data_image && ladder_name == "pixels" {
                        record.variant = "data".into();
                        sink.emit(&record)?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// `technique` with its defaults on the path the device would pick, `data` uploaded; volumes
/// cut at the configured fraction of their range.
fn growth_renderer(
    gpu: &Gpu,
    technique: Technique,
    data: &Dataset,
    config: &BenchConfig,
) -> Result<Box<dyn Renderer>> {
    let mut r = renderer::create(gpu, technique, &RendererOptions::default())?;
    if data.kind() == DataKind::Volume {
        r.set_appearance(
            gpu,
            &Appearance {
                iso: IsoValue::Normalized(config.iso_fraction),
                ..Appearance::default()
            },
        )?;
    }
    r.set_data(gpu, data)?;
    Ok(r)
}
