//! What the shell-traversal tests share: meshes, the optical model, cameras, the ways of
//! tracing the device runs, a reproducible generator and a poisoned-target GPU image.

use super::{skip, Need, Rng, TestGpu};
use glam::DVec3;
use tessera::path::Path;
use tessera::target::Target;
use tessera::tet::shell::{GpuShellMesh, RadianceBuffer, Shell};
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::procedural::{box_mesh, exploded};
use tessera_data::tet::shell::{LayoutKind, TraversalStats};
use tessera_data::tet::TetMesh;
use tessera_data::transfer::TransferFunction;
use tessera_data::{OrbitCamera, View};
use tessera_gpu::Gpu;

/// Two boxes side by side with a gap between them.
pub fn two_boxes() -> TetMesh {
    exploded(&box_mesh(2), 2, 0.5)
}

pub fn optics(density: f32) -> EmissionAbsorption {
    EmissionAbsorption::new(&TransferFunction::preset("cool-warm").unwrap(), density)
}

/// The ways of tracing the shell the device runs: the compute path always, the ray-tracing
/// pipeline where the device has it (else reported as skipped).
pub fn paths(gpu: &TestGpu) -> Vec<Path> {
    if gpu.has(Need::RayTracingPipeline) {
        vec![Path::Compute, Path::Graphics]
    } else {
        skip(
            "ray-tracing pipeline",
            &format!("{} lacks ray-tracing pipelines", gpu.caps().device_name),
        );
        vec![Path::Compute]
    }
}

/// Every layout on each of `paths`, the compute path of a layout first.
pub fn layouts_and_paths(paths: &[Path]) -> Vec<(LayoutKind, Path)> {
    LayoutKind::ALL
        .into_iter()
        .flat_map(|k| paths.iter().map(move |&p| (k, p)))
        .collect()
}

/// A point uniform in the cube of half-width `half` around the origin.
pub fn in_box(rng: &mut Rng, half: f64) -> DVec3 {
    DVec3::new(
        rng.range(-half, half),
        rng.range(-half, half),
        rng.range(-half, half),
    )
}

/// A pixel the shader never wrote keeps this (alpha 0x12; written pixels are opaque).
pub const POISON: u32 = 0x1234_5678;

/// The GPU image of `shell` in layout `kind`, the target poisoned first.
pub fn gpu_image(
    gpu: &Gpu,
    pass: &Shell,
    mesh: &GpuShellMesh,
    camera: &OrbitCamera,
    size: (u32, u32),
    background: [f32; 3],
) -> (tessera_data::RgbaImage, TraversalStats) {
    let target = Target::new(gpu, size.0, size.1).unwrap();
    target.poison(gpu, POISON).unwrap();
    let radiance = RadianceBuffer::new(gpu, size.0, size.1).unwrap();
    let params = pass.params(mesh, &View::of_unit_box(camera, size), background);
    let mut recorded = Ok(());
    gpu.submit("shell test image", |rec| {
        recorded = pass.record(rec, mesh, &target, &radiance, &params);
    })
    .unwrap();
    recorded.unwrap();
    let image = target.read(gpu).unwrap();
    assert!(
        image.pixels.iter().all(|&p| p != POISON),
        "pixels left unwritten"
    );
    (image, pass.read_stats(gpu).unwrap())
}

/// Pixels whose colour is not the background's: the mesh covers the view.
pub fn covered(image: &tessera_data::RgbaImage, background: [f32; 3]) -> f64 {
    let bg = tessera_data::shading::pack_rgba8([background[0], background[1], background[2], 1.0]);
    image.pixels.iter().filter(|&&p| p != bg).count() as f64 / image.pixels.len() as f64
}
