//! Isosurface extraction for users (the CLI's `extract`, Python's `marching_cubes`): a volume
//! and an isovalue in; a welded indexed mesh out (grid units, placed in physical units on
//! request), with the meshlets where the method makes them, and what the extraction cost. The GPU methods keep their output on
//! the device until here, where it is read back once.

use std::time::Instant;

use crate::error::{Error, Result};
use crate::iso::meshlets::{ExtractionPath, MeshletExtractor};
use crate::iso::minmax::MinMaxBuilder;
use crate::iso::pmb::PmbExtractor;
use crate::iso::PreparedVolume;
use crate::shaders;
use tessera_data::marching_cubes::marching_cubes_with;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::mesh::TriangleMesh;
use tessera_data::meshlets::MeshletMesh;
use tessera_data::pmb::PmbBlockSize;
use tessera_data::Volume;
use tessera_gpu::Gpu;

/// Which extractor produces the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceMethod {
    /// Single-threaded marching cubes on the CPU (`tessera_data::marching_cubes`).
    Cpu,
    /// Paper C's meshlet extraction on the GPU, on the given pipeline.
    Meshlets(ExtractionPath),
    /// Parallel Marching Blocks on the GPU (compute), blocks of the given size.
    Pmb(PmbBlockSize),
}

impl SurfaceMethod {
    /// The method `name` (`meshlets`, `pmb`, `pmb:XxYxZ` for a block size of
    /// [`PmbBlockSize::ALL`], or `cpu`) on `path` (`compute`, `mesh` or `auto`; only meshlets
    /// have two paths). `auto` takes the compute path: it gives the same meshlets bit for bit
    /// and runs on every device, where task and mesh stages run on few units of some GPUs
    /// (the H200's among them). Plain `pmb` takes 8×8×4 blocks.
    pub fn parse(name: &str, path: &str) -> Result<SurfaceMethod> {
        let extraction_path = match path {
            "compute" | "auto" => ExtractionPath::Compute,
            "mesh" => ExtractionPath::MeshShaders,
            _ => {
                return Err(Error::Invalid(format!(
                    "extraction path '{path}': choose compute, mesh or auto"
                )))
            }
        };
        let only_auto = |method: SurfaceMethod| {
            if path == "auto" {
                Ok(method)
            } else {
                Err(Error::Invalid(format!(
                    "the {name} method has no '{path}' path: leave the path at auto"
                )))
            }
        };
        match name.split_once(':') {
            None if name == "meshlets" => Ok(SurfaceMethod::Meshlets(extraction_path)),
            None if name == "cpu" => only_auto(SurfaceMethod::Cpu),
            None if name == "pmb" => only_auto(SurfaceMethod::Pmb(PmbBlockSize::default())),
            Some(("pmb", size)) => only_auto(SurfaceMethod::Pmb(PmbBlockSize::parse(size)?)),
            _ => Err(Error::Invalid(format!(
                "extraction method '{name}': choose meshlets, pmb[:XxYxZ] or cpu"
            ))),
        }
    }

    pub fn needs_gpu(self) -> bool {
        !matches!(self, SurfaceMethod::Cpu)
    }

    /// How the method names itself in output.
    pub fn describe(self) -> String {
        match self {
            SurfaceMethod::Cpu => "CPU marching cubes".into(),
            SurfaceMethod::Meshlets(ExtractionPath::Compute) => {
                "GPU meshlets (compute path)".into()
            }
            SurfaceMethod::Meshlets(ExtractionPath::MeshShaders) => {
                "GPU meshlets (task/mesh path)".into()
            }
            SurfaceMethod::Pmb(size) => format!("GPU PMB ({} blocks)", size.name()),
        }
    }
}

/// What one extraction cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ExtractionCost {
    /// Wall time of uploading the volume and building its min-max octree (GPU methods).
    pub prepare_ms: f64,
    /// The extraction itself: GPU timestamps of the attempt that fit (GPU methods), wall
    /// time on the CPU.
    pub extract_ms: f64,
    /// GPU extraction attempts (the first may overflow the initial buffers).
    pub attempts: u32,
    /// Wall time of reading the result back and welding it.
    pub readback_ms: f64,
    /// Bytes the surface takes where it was produced (the GPU's meshlet buffers, or the CPU
    /// mesh's arrays).
    pub stored_bytes: u64,
}

/// An extracted isosurface, in the volume's grid (sample index) units until
/// [`Surface::transformed`] places it.
#[derive(Debug, Clone, Default)]
pub struct Surface {
    /// One vertex per crossed grid edge (meshlet copies welded), triangles facing towards
    /// lower values.
    pub mesh: TriangleMesh,
    /// The meshlets as produced (border vertices once per meshlet), for methods that make
    /// them.
    pub meshlets: Option<MeshletMesh>,
    pub cost: ExtractionCost,
}

impl Surface {
    /// The surface moved by `transform`, e.g. `Volume::grid_to_physical` for physical units
    /// (normals turned and windings kept facing the same way, as `TriangleMesh::transformed`).
    pub fn transformed(self, transform: &glam::Affine3A) -> Surface {
        Surface {
            mesh: self.mesh.transformed(transform),
            meshlets: self.meshlets.map(|m| m.transformed(transform)),
            cost: self.cost,
        }
    }
}

fn elapsed_ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// Extracts the level set of `volume` at `iso_texel` (in the volume's stored sample units,
/// see `Volume::iso_to_texel`) with `method`, in grid units; ambiguous faces are cut by
/// `rule`. GPU methods need `gpu`.
pub fn extract_surface(
    gpu: Option<&Gpu>,
    volume: &Volume,
    iso_texel: f32,
    rule: AmbiguityRule,
    method: SurfaceMethod,
) -> Result<Surface> {
    if !iso_texel.is_finite() {
        return Err(Error::Invalid(format!(
            "isovalue {iso_texel} is not a number"
        )));
    }
    match method {
        SurfaceMethod::Cpu => {
            let start = Instant::now();
            let grid = marching_cubes_with(volume, iso_texel, rule);
            let extract_ms = elapsed_ms(start);
            let mesh = grid;
            let stored_bytes = (mesh.positions.len() * 24 + mesh.triangles.len() * 12) as u64;
            Ok(Surface {
                mesh,
                meshlets: None,
                cost: ExtractionCost {
                    extract_ms,
                    stored_bytes,
                    ..Default::default()
                },
            })
        }
        SurfaceMethod::Pmb(_) | SurfaceMethod::Meshlets(_) => {
            let gpu = gpu.ok_or_else(|| {
                Error::Invalid(format!("{} needs a GPU device", method.describe()))
            })?;
            extract_on_gpu(gpu, volume, iso_texel, rule, method)
        }
    }
}

/// The GPU methods: pipelines, then the volume and its octree (timed apart), then one
/// extraction grown until it fits, read back and welded.
fn extract_on_gpu(
    gpu: &Gpu,
    volume: &Volume,
    iso_texel: f32,
    rule: AmbiguityRule,
    method: SurfaceMethod,
) -> Result<Surface> {
    let compiler = shaders::compiler();
    let scalar = volume.scalar_type();
    let builder = MinMaxBuilder::new(gpu, &compiler, scalar)?;
    enum Extractor {
        Meshlets(MeshletExtractor),
        Pmb(PmbExtractor),
    }
    let extractor = match method {
        SurfaceMethod::Meshlets(path) => {
            Extractor::Meshlets(MeshletExtractor::new(gpu, &compiler, scalar, rule, path)?)
        }
        SurfaceMethod::Pmb(size) => {
            Extractor::Pmb(PmbExtractor::new(gpu, &compiler, scalar, rule, size)?)
        }
        SurfaceMethod::Cpu => {
            return Err(Error::Invalid("CPU marching cubes is no GPU method".into()))
        }
    };
    let start = Instant::now();
    let prepared = PreparedVolume::new(gpu, &builder, volume)?;
    let prepare_ms = elapsed_ms(start);
    let (gpu_ms, attempts, stored_bytes, start, meshlets, mesh) = match extractor {
        Extractor::Meshlets(ex) => {
            let mut out = ex.buffers(gpu, &prepared, Default::default())?;
            let e = ex.extract_into(gpu, &prepared, iso_texel, &mut out)?;
            let start = Instant::now();
            let meshlets = out.read(gpu)?;
            let mesh = meshlets.welded();
            let bytes = e.totals.stored_bytes();
            (e.gpu_ms, e.attempts, bytes, start, Some(meshlets), mesh)
        }
        Extractor::Pmb(ex) => {
            let mut out = ex.buffers(gpu, &prepared, Default::default())?;
            let e = ex.extract_into(gpu, &prepared, iso_texel, &mut out)?;
            let start = Instant::now();
            let mesh = out.read(gpu)?.welded();
            let bytes = e.totals.stored_bytes();
            (e.gpu_ms, e.attempts, bytes, start, None, mesh)
        }
    };
    Ok(Surface {
        mesh,
        meshlets,
        cost: ExtractionCost {
            prepare_ms,
            extract_ms: gpu_ms,
            attempts,
            readback_ms: elapsed_ms(start),
            stored_bytes,
        },
    })
}
