//! Tetrahedral-mesh benchmark scenarios.

use super::{time_frames, BenchRecord, FramePlan};
use super::{BenchConfig, RecordSink};
use crate::error::{Error, Result};
use crate::path::Path;
use crate::tet::interval::{
    path_support, GpuTetMesh, Integrand, Interval, IntervalOptions, OpticalTarget,
};
use tessera_data::scene::{DataKind, Dataset, LoadOptions, TetData};
use tessera_data::tet::procedural::box_mesh;
use tessera_data::tet::scalar_integral::mapping_range;
use tessera_data::transfer::{IntegrandTable, ScalarMode, TransferFunction, TABLE_KNOTS};
use tessera_data::OrbitCamera;
use tessera_gpu::Gpu;

/// One configuration of interval shading to time.
struct Variant {
    options: IntervalOptions,
    label: String,
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
/// inside meshes, and on large ones close up).
fn variants(
    gpu: &Gpu,
    wanted: &[Path],
    view: &str,
    scalar: Option<&Integrand>,
    small: bool,
) -> Vec<Variant> {
    let support = wanted_support(gpu, wanted);
    let mut out = Vec::new();
    let integrand = scalar.cloned().unwrap_or(Integrand::TetAbsorption);
    let kind = if scalar.is_some() {
        "scalar absorption"
    } else {
        "tet absorption"
    };
    if support.graphics {
        // Several tets per mesh workgroup against one (paper A §3.2); the far view suffices.
        let groups: &[u32] = if view == "far" && scalar.is_none() {
            &[1, 4, 16]
        } else {
            &[16]
        };
        for &n in groups {
            out.push(Variant {
                options: IntervalOptions {
                    integrand: integrand.clone(),
                    tets_per_workgroup: n,
                    ..IntervalOptions::new(Path::Graphics)
                },
                label: format!("{kind}, {n} tets/workgroup"),
            });
        }
    }
    if support.compute {
        // The pixel limit above which a tet goes to the tile pass; u32::MAX never tiles.
        // None: the automatic limit.
        let limits: &[Option<u32>] = if scalar.is_some() {
            &[None]
        } else if small && view != "inside" {
            &[None, Some(256), Some(4096), Some(65536), Some(u32::MAX)]
        } else {
            &[None, Some(256), Some(4096), Some(65536)]
        };
        for &limit in limits {
            out.push(Variant {
                options: IntervalOptions {
                    integrand: integrand.clone(),
                    inline_pixel_limit: limit,
                    ..IntervalOptions::new(Path::Compute)
                },
                label: match limit {
                    None => format!("{kind}, automatic tile limit"),
                    Some(u32::MAX) => format!("{kind}, untiled"),
                    Some(limit) => format!("{kind}, tiles above {limit} px"),
                },
            });
        }
    }
    out
}

/// Interval shading of procedural tet boxes of about 61 k, 959 k and 2.4 M tets (the sizes of
/// paper A's Table 1), far, close and inside views, at 3840×2160 (`--quick`: small meshes and
/// image), on both paths with their variants, and scalar integration through a transfer
/// function on the middle mesh; then the asteroid field. `--data` measures one mesh instead: a
/// file (e.g. the tetgen bunny), `tets:box:N`, `tets:sphere:N` or `tets:asteroids:COUNT`.
pub fn interval(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let compiler = crate::shaders::compiler();
    let size = if config.quick {
        (256, 144)
    } else {
        (3840, 2160)
    };
    let bench = MeshBench {
        compiler: &compiler,
        paths: &config.paths,
        plan,
        size,
    };
    let views = [("far", 2.4f32), ("close", 1.4), ("inside", 0.3)];
    let tf = TransferFunction::preset("cool-warm")?;
    let scalar = Integrand::Scalar {
        mode: ScalarMode::Absorption,
        table: IntegrandTable::new(&tf, ScalarMode::Absorption, 4.0, TABLE_KNOTS),
    };
    if let Some(spec) = config
        .data
        .as_deref()
        .filter(|d| DataKind::of_spec(d) == DataKind::Tets)
    {
        if let Some(count) = spec.strip_prefix("tets:asteroids:") {
            let count = count
                .parse()
                .map_err(|_| Error::Invalid(format!("'{spec}': bad COUNT")))?;
            return asteroids(gpu, &compiler, &config.paths, count, plan, sink, size);
        }
        let tets = Dataset::load(spec, &LoadOptions::default())?;
        let Dataset::Tets(TetData { mesh, .. }) = tets else {
            unreachable!("tet specs load as meshes")
        };
        let name = std::path::Path::new(spec)
            .file_name()
            .map_or(spec.to_string(), |n| n.to_string_lossy().into_owned());
        let scalar = mesh.scalars.is_some().then_some(&scalar);
        return bench.run(gpu, &mesh, &name, &views, scalar, sink);
    }
    // n³ cells of 6 tets each.
    let cells: &[u32] = if config.quick {
        &[6, 10]
    } else {
        &[22, 54, 74]
    };
    for (i, &n) in cells.iter().enumerate() {
        let mesh = box_mesh(n);
        let scalar = (i == cells.len() / 2).then_some(&scalar);
        bench.run(gpu, &mesh, "box", &views, scalar, sink)?;
    }
    let count = if config.quick { 500 } else { 10_000 };
    asteroids(gpu, &compiler, &config.paths, count, plan, sink, size)
}

/// Times one mesh's views with every variant.
struct MeshBench<'a> {
    compiler: &'a tessera_gpu::ShaderCompiler,
    paths: &'a [Path],
    plan: FramePlan,
    size: (u32, u32),
}

impl MeshBench<'_> {
    fn run(
        &self,
        gpu: &Gpu,
        mesh: &tessera_data::tet::TetMesh,
        name: &str,
        views: &[(&str, f32)],
        scalar: Option<&Integrand>,
        sink: &mut dyn RecordSink,
    ) -> Result<()> {
        if scalar.is_some() {
            // The same check as before the upload: scalars with a finite range.
            mapping_range(mesh, None, name)?;
        }
        let gpu_mesh = GpuTetMesh::upload(gpu, mesh)?;
        let result = views.iter().try_for_each(|&(view, distance)| {
            let camera = OrbitCamera {
                distance,
                ..OrbitCamera::default()
            };
            let small = mesh.tets.len() < 100_000;
            let mut all = variants(gpu, self.paths, view, None, small);
            if let Some(s) = scalar {
                all.extend(variants(gpu, self.paths, view, Some(s), small));
            }
            all.iter().try_for_each(|variant| {
                let dataset = format!("{name} {} tets, {view}", mesh.tets.len());
                let timed = time_variant(
                    gpu,
                    self.compiler,
                    variant,
                    &gpu_mesh,
                    &camera,
                    self.size,
                    self.plan,
                )?;
                let mut r = timed.into_record(gpu, &dataset, variant, self.plan, self.size);
                r.counts.insert("tets".into(), mesh.tets.len() as f64);
                if let Some(ms) = r.median_ms("interval") {
                    r.counts
                        .insert("mtets_per_s".into(), mesh.tets.len() as f64 / ms / 1e3);
                }
                sink.emit(&r)
            })
        });
        result
    }
}

/// Paper A's asteroid field: `count` (10,000 in the paper) asteroids, one bounding tet each, sphere-traced along
/// their intervals; seen from outside and from within the field.
fn asteroids(
    gpu: &Gpu,
    compiler: &tessera_gpu::ShaderCompiler,
    paths: &[Path],
    count: u32,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
    (w, h): (u32, u32),
) -> Result<()> {
    let mesh = tessera_data::tet::asteroids::asteroid_field(count, 1);
    let gpu_mesh = GpuTetMesh::upload_asteroids(gpu, &mesh)?;
    let support = wanted_support(gpu, paths);
    let mut all = Vec::new();
    if support.graphics {
        for n in [1, 16] {
            all.push(Variant {
                options: IntervalOptions {
                    integrand: Integrand::Asteroids,
                    tets_per_workgroup: n,
                    ..IntervalOptions::new(Path::Graphics)
                },
                label: format!("asteroids, {n} tets/workgroup"),
            });
        }
    }
    if support.compute && gpu.caps().buffer_int64_atomics {
        all.push(Variant {
            options: IntervalOptions {
                integrand: Integrand::Asteroids,
                ..IntervalOptions::new(Path::Compute)
            },
            label: "asteroids, automatic tile limit".into(),
        });
    }
    for (view, distance) in [("outside", 1.5f32), ("inside", 0.15)] {
        let camera = OrbitCamera {
            distance,
            ..OrbitCamera::default()
        };
        for variant in &all {
            let dataset = format!("asteroids {count}, {view}");
            let timed = time_variant(gpu, compiler, variant, &gpu_mesh, &camera, (w, h), plan)?;
            let mut r = timed.into_record(gpu, &dataset, variant, plan, (w, h));
            r.counts.insert("tets".into(), f64::from(count));
            sink.emit(&r)?;
        }
    }
    Ok(())
}

struct Timed {
    stages: Vec<crate::bench::StageStats>,
    tiled: u32,
    overflowed: u32,
}

impl Timed {
    fn into_record(
        self,
        gpu: &Gpu,
        dataset: &str,
        variant: &Variant,
        plan: FramePlan,
        (w, h): (u32, u32),
    ) -> BenchRecord {
        let path = variant.options.path.name();
        let mut r = BenchRecord::new(gpu, "interval", "interval", path, dataset);
        (r.width, r.height, r.warmup, r.frames, r.stages) =
            (w, h, plan.warmup, plan.frames, self.stages);
        r.variant = variant.label.clone();
        r.counts.insert("tiled_tets".into(), f64::from(self.tiled));
        r.counts
            .insert("overflowed_tets".into(), f64::from(self.overflowed));
        r
    }
}

fn time_variant(
    gpu: &Gpu,
    compiler: &tessera_gpu::ShaderCompiler,
    variant: &Variant,
    mesh: &GpuTetMesh,
    camera: &OrbitCamera,
    (w, h): (u32, u32),
    plan: FramePlan,
) -> Result<Timed> {
    let interval = Interval::new(gpu, compiler, &variant.options)?;
    let target = interval.target(gpu, w, h)?;
    run_frames(gpu, &interval, mesh, &target, camera, plan)
}

fn run_frames(
    gpu: &Gpu,
    interval: &Interval,
    mesh: &GpuTetMesh,
    target: &OpticalTarget,
    camera: &OrbitCamera,
    plan: FramePlan,
) -> Result<Timed> {
    let params = interval.params(mesh, camera, target.width, target.height);
    let mut recorded = Ok(());
    let stages = time_frames(gpu, plan, 1, |rec, timer| {
        let r = timer.scope(rec, "interval", |rec| {
            interval.record(rec, mesh, target, &params)
        });
        recorded = recorded.clone().and(r.map_err(|e| e.to_string()));
    });
    recorded.map_err(Error::Invalid)?;
    // One more frame for the counters.
    let frame = interval.render(gpu, mesh, target, camera)?;
    Ok(Timed {
        stages: stages?,
        tiled: frame.tiled,
        overflowed: frame.overflowed,
    })
}
