//! Tetrahedral-mesh benchmark scenarios: interval shading through the front door, one
//! renderer per variant (path, tets per workgroup, tile limit, compute scheme, integrand).

use super::frames::time_mono;
use super::{BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::{Error, Result};
use crate::path::{Path, PathChoice};
use crate::renderer::{self, IntervalTuning, Renderer, RendererOptions, Technique};
use crate::tet::interval::{
    path_support, ComputeScheme, SubgroupDraw, DEFAULT_INLINE_PIXEL_LIMIT,
    SUBGROUP_DRAW_ABOVE_PIXELS,
};
use std::collections::BTreeMap;
use tessera_data::scene::{Appearance, DataKind, Dataset, IntegrandChoice, LoadOptions};
use tessera_data::transfer::ScalarMode;
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// One configuration of interval shading to time.
struct Variant {
    options: RendererOptions,
    look: Appearance,
    label: String,
}

impl Variant {
    fn new(path: Path, tuning: IntervalTuning, integrand: IntegrandChoice, label: String) -> Self {
        let choice = match path {
            Path::Graphics => PathChoice::Graphics,
            Path::Compute => PathChoice::Compute,
        };
        Variant {
            options: RendererOptions {
                path: choice,
                interval: tuning,
                ..RendererOptions::default()
            },
            look: Appearance {
                integrand,
                ..Appearance::default()
            },
            label,
        }
    }
}

/// The paths the device has, of those `wanted` (all where none is named).
fn wanted_support(gpu: &Gpu, wanted: &[Path]) -> crate::path::Support {
    let mut support = path_support(gpu.caps());
    let wants = |p: Path| wanted.is_empty() || wanted.contains(&p);
    support.graphics &= wants(Path::Graphics);
    support.compute &= wants(Path::Compute);
    support
}

/// `small`: whether the untiled compute variant is affordable (it takes seconds per frame from
/// inside meshes, and on large ones close up). `subgroup_ways`: also the per-tet pass with
/// each way of [`SUBGROUP_WAYS`] (listed only when asked for: they multiply the cells).
fn variants(
    gpu: &Gpu,
    wanted: &[Path],
    view: &str,
    scalar: bool,
    small: bool,
    subgroup_ways: bool,
) -> Vec<Variant> {
    let support = wanted_support(gpu, wanted);
    let mut out = Vec::new();
    let (integrand, kind) = if scalar {
        (
            IntegrandChoice::Scalar(ScalarMode::Absorption),
            "scalar absorption",
        )
    } else {
        (IntegrandChoice::TetAbsorption, "tet absorption")
    };
    if support.graphics {
        // Several tets per mesh workgroup against one (paper A §3.2); the far view suffices.
        let groups: &[u32] = if view == "far" && !scalar {
            &[1, 4, 16]
        } else {
            &[16]
        };
        for &n in groups {
            let tuning = IntervalTuning {
                tets_per_workgroup: n,
                ..IntervalTuning::default()
            };
            let label = format!("{kind}, {n} tets/workgroup");
            out.push(Variant::new(Path::Graphics, tuning, integrand, label));
        }
    }
    if support.compute {
        // The pixel limit above which a tet goes to the tile pass; u32::MAX never tiles.
        // None: the default limit (DEFAULT_INLINE_PIXEL_LIMIT, so not listed again).
        let limits: &[Option<u32>] = if scalar {
            &[None]
        } else if small && view != "inside" {
            &[None, Some(65536), Some(u32::MAX)]
        } else {
            &[None, Some(65536)]
        };
        for &limit in limits {
            let tuning = IntervalTuning {
                inline_pixel_limit: limit,
                compute_scheme: ComputeScheme::PerTet,
                ..IntervalTuning::default()
            };
            let label = match limit {
                None => format!("{kind}, tiles above {DEFAULT_INLINE_PIXEL_LIMIT} px"),
                Some(u32::MAX) => format!("{kind}, untiled"),
                Some(limit) => format!("{kind}, tiles above {limit} px"),
            };
            out.push(Variant::new(Path::Compute, tuning, integrand, label));
        }
        for way in SUBGROUP_WAYS.iter().filter(|_| subgroup_ways) {
            let tuning = IntervalTuning {
                compute_scheme: ComputeScheme::PerTet,
                subgroup_draw: *way,
                ..IntervalTuning::default()
            };
            let label = format!(
                "{kind}, tiles above {DEFAULT_INLINE_PIXEL_LIMIT} px, {}",
                way.name()
            );
            out.push(Variant::new(Path::Compute, tuning, integrand, label));
        }
        out.push(scheme(
            ComputeScheme::Binned,
            integrand,
            &format!("{kind}, binned"),
        ));
        out.push(scheme(
            ComputeScheme::Auto,
            integrand,
            &format!("{kind}, auto"),
        ));
    }
    out
}

/// The per-tet pass's ways of drawing with subgroups that `--variants subgroup` compares: the
/// default (`Above(SUBGROUP_DRAW_ABOVE_PIXELS)`), none, a higher limit, and limits chosen per
/// subgroup with three set-up costs.
const SUBGROUP_WAYS: [SubgroupDraw; 6] = [
    SubgroupDraw::Above(SUBGROUP_DRAW_ABOVE_PIXELS),
    SubgroupDraw::Off,
    SubgroupDraw::Above(256),
    SubgroupDraw::Chosen { setup_pixels: 32 },
    SubgroupDraw::Chosen { setup_pixels: 128 },
    SubgroupDraw::Chosen { setup_pixels: 512 },
];

/// The compute path's binned or automatic scheme (the tile limit the automatic one, for the
/// tets the binned lists have no room for).
fn scheme(compute_scheme: ComputeScheme, integrand: IntegrandChoice, label: &str) -> Variant {
    let tuning = IntervalTuning {
        compute_scheme,
        ..IntervalTuning::default()
    };
    Variant::new(Path::Compute, tuning, integrand, label.to_string())
}

/// Interval shading of procedural tet boxes of about 61 k, 959 k and 2.4 M tets (the sizes of
/// paper A's Table 1), far, close and inside views, at 3840×2160 or each of `config.sizes`
/// (`--quick`: small meshes and image), on both paths with their variants, and scalar
/// integration through a transfer function on the middle mesh; then the asteroid field.
/// `--data` measures one mesh instead: a file (e.g. the tetgen bunny), `tets:box:N`,
/// `tets:sphere:N` or `tets:asteroids:COUNT`. `config.variants` keeps only the variants whose
/// label holds it: an error when none does.
pub fn interval(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let mut counted = CountedSink {
        inner: sink,
        records: 0,
    };
    interval_meshes(gpu, config, plan, &mut counted)?;
    match &config.variants {
        Some(text) if counted.records == 0 => Err(Error::Invalid(format!(
            "no interval variant's label holds '{text}' (labels are such as \
             'tet absorption, binned' or 'scalar absorption, auto')"
        ))),
        _ => Ok(()),
    }
}

/// Passes records on, counting them.
struct CountedSink<'a> {
    inner: &'a mut dyn RecordSink,
    records: usize,
}

impl RecordSink for CountedSink<'_> {
    fn emit(&mut self, record: &BenchRecord) -> Result<()> {
        self.records += 1;
        self.inner.emit(record)
    }

    fn note(&mut self, text: &str) {
        self.inner.note(text);
    }
}

fn interval_meshes(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let sizes = match (config.sizes.is_empty(), config.quick) {
        (false, _) => config.sizes.clone(),
        (true, true) => vec![(256, 144)],
        (true, false) => vec![(3840, 2160)],
    };
    let benches: Vec<MeshBench> = sizes
        .into_iter()
        .map(|size| MeshBench {
            paths: &config.paths,
            wanted: config.variants.as_deref(),
            plan,
            size,
        })
        .collect();
    let views = [("far", 2.4f32), ("close", 1.4), ("inside", 0.3)];
    let load = |spec: &str| Dataset::load(spec, &LoadOptions::default());
    if let Some(spec) = config
        .data
        .as_deref()
        .filter(|d| DataKind::of_spec(d) == DataKind::Tets)
    {
        let data = load(spec)?;
        let name = std::path::Path::new(spec)
            .file_name()
            .map_or(spec.to_string(), |n| n.to_string_lossy().into_owned());
        for bench in &benches {
            if spec.starts_with("tets:asteroids:") {
                bench.asteroids(gpu, &data, sink)?;
            } else {
                bench.run(gpu, &data, &name, &views, true, sink)?;
            }
        }
        return Ok(());
    }
    // n³ cells of 6 tets each.
    let cells: &[u32] = if config.quick {
        &[6, 10]
    } else {
        &[22, 54, 74]
    };
    for (i, &n) in cells.iter().enumerate() {
        let data = load(&format!("tets:box:{n}"))?;
        for bench in &benches {
            bench.run(gpu, &data, "box", &views, i == cells.len() / 2, sink)?;
        }
    }
    let count = if config.quick { 500 } else { 10_000 };
    let asteroids = load(&format!("tets:asteroids:{count}"))?;
    for bench in &benches {
        bench.asteroids(gpu, &asteroids, sink)?;
    }
    Ok(())
}

/// Times one mesh's views with every variant.
struct MeshBench<'a> {
    paths: &'a [Path],
    /// Only the variants whose label holds this text.
    wanted: Option<&'a str>,
    plan: FramePlan,
    size: (u32, u32),
}

impl MeshBench<'_> {
    /// `scalar`: also through the transfer function, where the mesh has vertex scalars.
    fn run(
        &self,
        gpu: &Gpu,
        data: &Dataset,
        name: &str,
        views: &[(&str, f32)],
        scalar: bool,
        sink: &mut dyn RecordSink,
    ) -> Result<()> {
        let Dataset::Tets(tets) = data else {
            return Err(renderer::wrong_data(Technique::Interval, data));
        };
        let count = tets.mesh.tets.len();
        let scalar = scalar && tets.mesh.scalars.is_some();
        let small = count < 100_000;
        // A renderer per variant, made (and the mesh uploaded) the first time it is needed.
        let mut renderers: BTreeMap<String, Box<dyn Renderer>> = BTreeMap::new();
        for &(view, distance) in views {
            let ways = self.wanted.is_some_and(|text| text.contains("subgroup"));
            let mut all = variants(gpu, self.paths, view, false, small, ways);
            if scalar {
                all.extend(variants(gpu, self.paths, view, true, small, ways));
            }
            self.keep_wanted(&mut all);
            for variant in &all {
                let dataset = format!("{name} {count} tets, {view}");
                let camera = OrbitCamera {
                    distance,
                    ..OrbitCamera::default()
                };
                let r = match renderers.entry(variant.label.clone()) {
                    std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
                    std::collections::btree_map::Entry::Vacant(e) => {
                        e.insert(interval_renderer(gpu, variant, data)?)
                    }
                };
                let mut record = self.time(gpu, r.as_mut(), &camera, &dataset, variant)?;
                record.counts.insert("tets".into(), count as f64);
                // The binned scheme times its binning apart; the rate counts both.
                let binning = record.median_ms("binning").unwrap_or(0.0);
                if let Some(ms) = record.median_ms("interval").map(|ms| ms + binning) {
                    record
                        .counts
                        .insert("mtets_per_s".into(), count as f64 / ms / 1e3);
                }
                sink.emit(&record)?;
            }
        }
        Ok(())
    }

    /// Paper A's asteroid field (10,000 asteroids in the paper), one bounding tet each,
    /// sphere-traced along their intervals; seen from outside and from within the field.
    fn asteroids(&self, gpu: &Gpu, data: &Dataset, sink: &mut dyn RecordSink) -> Result<()> {
        let Dataset::Tets(tets) = data else {
            return Err(renderer::wrong_data(Technique::Interval, data));
        };
        let count = tets.mesh.tets.len();
        let support = wanted_support(gpu, self.paths);
        let mut all = Vec::new();
        // The integrand follows the data: asteroids are always sphere-traced.
        let integrand = IntegrandChoice::Auto;
        if support.graphics {
            for n in [1, 16] {
                let tuning = IntervalTuning {
                    tets_per_workgroup: n,
                    ..IntervalTuning::default()
                };
                let label = format!("asteroids, {n} tets/workgroup");
                all.push(Variant::new(Path::Graphics, tuning, integrand, label));
            }
        }
        if support.compute && gpu.caps().buffer_int64_atomics {
            let label = format!("asteroids, tiles above {DEFAULT_INLINE_PIXEL_LIMIT} px");
            let tuning = IntervalTuning {
                compute_scheme: ComputeScheme::PerTet,
                ..IntervalTuning::default()
            };
            all.push(Variant::new(Path::Compute, tuning, integrand, label));
            all.push(scheme(
                ComputeScheme::Binned,
                integrand,
                "asteroids, binned",
            ));
            all.push(scheme(ComputeScheme::Auto, integrand, "asteroids, auto"));
        }
        self.keep_wanted(&mut all);
        for variant in &all {
            let mut r = interval_renderer(gpu, variant, data)?;
            for (view, distance) in [("outside", 1.5f32), ("inside", 0.15)] {
                let camera = OrbitCamera {
                    distance,
                    ..OrbitCamera::default()
                };
                let dataset = format!("asteroids {count}, {view}");
                let mut record = self.time(gpu, r.as_mut(), &camera, &dataset, variant)?;
                record.counts.insert("tets".into(), count as f64);
                sink.emit(&record)?;
            }
        }
        Ok(())
    }

    fn keep_wanted(&self, variants: &mut Vec<Variant>) {
        if let Some(text) = self.wanted {
            variants.retain(|v| v.label.contains(text));
        }
    }

    fn time(
        &self,
        gpu: &Gpu,
        r: &mut dyn Renderer,
        camera: &OrbitCamera,
        dataset: &str,
        variant: &Variant,
    ) -> Result<BenchRecord> {
        let view = r.view(camera, self.size)?;
        let stages = time_mono(gpu, r, &view, self.plan, 1, None)?;
        let path = r.path().name();
        let mut record = BenchRecord::new(gpu, "interval", "interval", path, dataset);
        (
            record.width,
            record.height,
            record.warmup,
            record.frames,
            record.stages,
        ) = (
            self.size.0,
            self.size.1,
            self.plan.warmup,
            self.plan.frames,
            stages,
        );
        record.variant = variant.label.clone();
        record.add_frame_stats(&r.stats());
        Ok(record)
    }
}

fn interval_renderer(gpu: &Gpu, variant: &Variant, data: &Dataset) -> Result<Box<dyn Renderer>> {
    let mut r = renderer::create(gpu, Technique::Interval, &variant.options)?;
    r.set_appearance(gpu, &variant.look)?;
    r.set_data(gpu, data)?;
    Ok(r)
}
