//! Shell traversal (paper B) against its Table 1: tet boxes of about 1 M, 1.3 M, 2.9 M and
//! 10 M tets (the paper's Jets, Plasma64 and Fusion sizes, and beyond) at 1024², emission and
//! absorption alone and with all effects (shadows, ambient occlusion, gradient shading; the
//! tets' lighting reused from frame to frame, and cast again every frame), in each layout on
//! each way of tracing the shell, and the shell traces alone; and interval shading (paper A) of the same
//! mesh and transfer function (scalar absorption: interval shading has no emission–absorption
//! integrand), on its own fastest settings.

use super::frames::{time_mono, EachFrame};
use super::{BenchConfig, BenchRecord, FramePlan, RecordSink};
use crate::error::Result;
use crate::path::{Path, PathChoice};
use crate::renderer::{self, AmbientOcclusion, Light, Renderer, RendererOptions, Technique};
use crate::target::Target;
use crate::tet::shell::{GpuShellMesh, RadianceBuffer, Shell, ShellOptions};
use glam::DVec3;
use tessera_data::scene::{Appearance, DataKind, Dataset, IntegrandChoice, LoadOptions};
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::shell::{LayoutKind, ShellMesh, Tet16, Tet20, Tet32};
use tessera_data::transfer::ScalarMode;
use tessera_data::{OrbitCamera, View};
use tessera_gpu::Gpu;

/// Hemisphere rays per tet for ambient occlusion, and their reach (the mesh's longest side is
/// 1): the paper names neither.
const AO_SAMPLES: u32 = 4;
const AO_RADIUS: f32 = 0.1;

fn layout_bytes(kind: LayoutKind) -> usize {
    match kind {
        LayoutKind::Tet32 => std::mem::size_of::<Tet32>(),
        LayoutKind::Tet20 => std::mem::size_of::<Tet20>(),
        LayoutKind::Tet16 => std::mem::size_of::<Tet16>(),
    }
}

/// The ways of tracing the shell to measure: those asked for that the device has.
fn shell_paths(gpu: &Gpu, wanted: &[Path], sink: &mut dyn RecordSink) -> Vec<Path> {
    let support = crate::tet::shell::path_support(gpu.caps());
    let wants = |p: Path| wanted.is_empty() || wanted.contains(&p);
    let mut paths = Vec::new();
    if wants(Path::Compute) {
        paths.push(Path::Compute);
    }
    if wants(Path::Graphics) {
        if support.graphics {
            paths.push(Path::Graphics);
        } else {
            sink.note(&format!(
                "shell: {} has no ray-tracing pipelines; the graphics path is skipped",
                gpu.caps().device_name
            ));
        }
    }
    paths
}

pub fn shell(
    gpu: &Gpu,
    config: &BenchConfig,
    plan: FramePlan,
    sink: &mut dyn RecordSink,
) -> Result<()> {
    let size = if config.quick {
        (128, 128)
    } else {
        (1024, 1024)
    };
    let load = |spec: &str| Dataset::load(spec, &LoadOptions::default());
    let meshes: Vec<(String, Dataset)> = match config
        .data
        .as_deref()
        .filter(|d| DataKind::of_spec(d) == DataKind::Tets)
    {
        Some(spec) => {
            let name = std::path::Path::new(spec)
                .file_name()
                .map_or(spec.to_string(), |n| n.to_string_lossy().into_owned());
            vec![(name, load(spec)?)]
        }
        None => {
            // n³ cells of 6 tets: 0.998 M, 1.30 M, 2.85 M and 10.4 M tets.
            let cells: &[u32] = if config.quick {
                &[4, 6]
            } else {
                &[55, 60, 78, 120]
            };
            cells
                .iter()
                .map(|&n| Ok(("box".to_string(), load(&format!("tets:box:{n}"))?)))
                .collect::<Result<_>>()?
        }
    };
    let paths = shell_paths(gpu, &config.paths, sink);
    let camera = OrbitCamera {
        distance: 2.0,
        ..OrbitCamera::default()
    };
    for (name, data) in &meshes {
        let Dataset::Tets(tets) = data else {
            return Err(renderer::wrong_data(Technique::Shell, data));
        };
        let count = tets.mesh.tets.len();
        let dataset = format!("{name} {count} tets");
        let measure = MeshRun {
            gpu,
            data,
            camera: &camera,
            size,
            plan,
            dataset: &dataset,
            tets: count,
        };
        // Building the layouts of a 10 M-tet mesh again for every variant would take longer
        // than timing it: the largest meshes get the layout the paper reports memory for.
        let layouts: &[LayoutKind] = if count > 5_000_000 {
            &[LayoutKind::Tet20]
        } else {
            &LayoutKind::ALL
        };
        for &path in &paths {
            for &kind in layouts {
                // E+A; all effects lit once and reused (the light and look stay, as while the
                // camera turns); all effects lit again every frame (as while the light moves).
                for (effects, relight) in [(false, false), (true, false), (true, true)] {
                    let mut options = RendererOptions {
                        path: match path {
                            Path::Graphics => PathChoice::Graphics,
                            Path::Compute => PathChoice::Compute,
                        },
                        layout: kind,
                        ..RendererOptions::default()
                    };
                    if effects {
                        options.shadows = Some(Light::above(DVec3::Y));
                        options.ao = Some(AmbientOcclusion::new(AO_SAMPLES, AO_RADIUS)?);
                        options.gradient = true;
                    }
                    let label = format!(
                        "{}, {}",
                        kind.name(),
                        match (effects, relight) {
                            (false, _) => "E+A",
                            (true, false) => "all effects",
                            (true, true) => "all effects, relit every frame",
                        }
                    );
                    let look = Appearance::default();
                    // Setting the look again discards the tets' lighting.
                    let set_look = |_: u32, r: &mut dyn Renderer| r.set_appearance(gpu, &look);
                    let each_frame: EachFrame = relight.then_some(&set_look);
                    let mut record =
                        measure.time(Technique::Shell, &options, &look, &label, each_frame)?;
                    record
                        .counts
                        .insert("bytes_per_tet".into(), layout_bytes(kind) as f64);
                    sink.emit(&record)?;
                }
            }
        }
        for &path in &paths {
            let record = measure.time_traces(path)?;
            sink.emit(&record)?;
        }
        if tets.mesh.scalars.is_some() {
            let look = Appearance {
                integrand: IntegrandChoice::Scalar(ScalarMode::Absorption),
                ..Appearance::default()
            };
            match measure.time(
                Technique::Interval,
                &RendererOptions::default(),
                &look,
                "scalar absorption, automatic path and tiling",
                None,
            ) {
                Ok(record) => sink.emit(&record)?,
                Err(e) => sink.note(&format!("interval shading of {dataset}: {e}")),
            }
        }
    }
    Ok(())
}

/// One mesh's measurements.
struct MeshRun<'a> {
    gpu: &'a Gpu,
    data: &'a Dataset,
    camera: &'a OrbitCamera,
    size: (u32, u32),
    plan: FramePlan,
    dataset: &'a str,
    tets: usize,
}

impl MeshRun<'_> {
    /// The pixel pass in Tet20 finding every segment's exit and entry faces without marching
    /// it: the shell traces' share of the E+A frame.
    fn time_traces(&self, path: Path) -> Result<BenchRecord> {
        let gpu = self.gpu;
        let Dataset::Tets(tets) = self.data else {
            return Err(renderer::wrong_data(Technique::Shell, self.data));
        };
        let shell = ShellMesh::build(&tets.mesh)?;
        let options = ShellOptions {
            traces_only: true,
            ..ShellOptions::on(LayoutKind::Tet20, path)
        };
        let look = Appearance::default();
        let optics = EmissionAbsorption::new(&look.transfer, look.density);
        let pass = Shell::new(gpu, &crate::shaders::compiler(), &options, &optics)?;
        let mesh = GpuShellMesh::upload_for(gpu, &shell, LayoutKind::Tet20, path)?;
        let view = View::of_unit_box(self.camera, self.size);
        let target = Target::new(gpu, self.size.0, self.size.1)?;
        let radiance = RadianceBuffer::new(gpu, self.size.0, self.size.1)?;
        let params = pass.params(&mesh, &view, [0.0; 3]);
        let mut recorded = Ok(());
        let stages = tessera_gpu::timing::time_frames(gpu, self.plan, 1, |rec, timer| {
            let frame = timer.scope(rec, "shell traces", |rec| {
                pass.record(rec, &mesh, &target, &radiance, &params)
            });
            if recorded.is_ok() {
                recorded = frame;
            }
        })?;
        recorded?;
        let stats = pass.read_stats(gpu)?;
        let mut record = BenchRecord::new(gpu, "shell", "shell", path.name(), self.dataset);
        record.width = self.size.0;
        record.height = self.size.1;
        record.warmup = self.plan.warmup;
        record.frames = self.plan.frames;
        record.stages = stages;
        record.variant = "tet20, shell traces only".into();
        record.counts.insert("tets".into(), self.tets as f64);
        record
            .counts
            .insert("segments".into(), stats.segments as f64);
        record
            .counts
            .insert("shell_faces".into(), shell.faces.len() as f64);
        Ok(record)
    }

    fn time(
        &self,
        technique: Technique,
        options: &RendererOptions,
        look: &Appearance,
        label: &str,
        each_frame: EachFrame,
    ) -> Result<BenchRecord> {
        let gpu = self.gpu;
        let mut r = renderer::create(gpu, technique, options)?;
        r.set_appearance(gpu, look)?;
        r.set_data(gpu, self.data)?;
        let view = r.view(self.camera, self.size)?;
        let stages = time_mono(gpu, r.as_mut(), &view, self.plan, 1, each_frame)?;
        let mut record = BenchRecord::new(
            gpu,
            "shell",
            technique.name(),
            r.path().name(),
            self.dataset,
        );
        record.width = self.size.0;
        record.height = self.size.1;
        record.warmup = self.plan.warmup;
        record.frames = self.plan.frames;
        record.stages = stages;
        record.variant = label.to_string();
        record.add_frame_stats(&r.stats());
        record.counts.insert("tets".into(), self.tets as f64);
        record
            .counts
            .insert("gpu_mesh_bytes".into(), r.counters().data_bytes as f64);
        if let Some(ms) = record.frame_ms() {
            record.counts.insert("fps".into(), 1e3 / ms);
        }
        Ok(record)
    }
}
