//! Ambiguous faces on every GPU extraction path: the mesh shaders' capture and the compute
//! extraction must equal the CPU marching cubes triangle for triangle under both rules, on
//! volumes made of ambiguous cells.

mod common;

use common::{
    assert_clean, assert_same_triangles, checkerboard, field, gpu, list_triangles_in_grid, Need,
    TestGpu,
};
use tessera::iso::direct::compute::{DirectExtract, TriangleLists};
use tessera::iso::direct::{Direct, FrameOptions, RasterTarget};
use tessera::iso::minmax::MinMaxBuilder;
use tessera::iso::PreparedVolume;
use tessera::shaders;
use tessera_data::marching_cubes::{marching_cubes_with, AmbiguityRule};
use tessera_data::{OrbitCamera, Volume};

const RULES: [AmbiguityRule; 2] = [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk];

/// `(volume, iso)` pairs whose cells are mostly ambiguous: one cell with 1 at two diagonal
/// corners of a face (saddle value 0.5, so the decider joins them at 0.2 and not at 0.8),
/// hashed noise whose faces have saddles of every value, and the checkerboard, whose saddles
/// equal the isovalue (the tie every path must break alike).
fn ambiguous_volumes() -> Vec<(Volume, f32)> {
    let diagonal = field("face-diagonal cell", [2; 3], |p| {
        f32::from(p.z == 0.0 && p.x == p.y)
    });
    let saddles = field("noise saddles", [21, 18, 13], |p| {
        // A multiplicative hash of the sample position: reproducible, no generator needed.
        let [x, y, z] = p.to_array().map(|c| c as u32);
        let h =
            (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663) ^ z.wrapping_mul(83_492_791))
                .wrapping_mul(2_654_435_761);
        (h >> 8) as f32 / (1u32 << 24) as f32
    });
    vec![
        (diagonal.clone(), 0.2),
        (diagonal, 0.8),
        (saddles.clone(), 0.5),
        (saddles, 0.3),
        (checkerboard([10, 9, 8]), 0.5),
    ]
}

#[test]
fn rules_differ_on_the_test_volumes() {
    // Otherwise the GPU comparisons below could not tell the rules apart.
    for (volume, iso) in ambiguous_volumes() {
        let [decider, vtk] = RULES.map(|r| marching_cubes_with(&volume, iso, r));
        let differs =
            decider.canonical_triangle_multiset(1e-4) != vtk.canonical_triangle_multiset(1e-4);
        let expected = !(volume.name() == "face-diagonal cell" && iso > 0.5);
        assert_eq!(differs, expected, "{} at {iso}", volume.name());
    }
}

#[test]
fn compute_extraction_equals_cpu_on_ambiguous_cells() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    for rule in RULES {
        for (volume, iso) in ambiguous_volumes() {
            let name = format!("{} at {iso}, {rule:?}", volume.name());
            let cpu = marching_cubes_with(&volume, iso, rule);
            assert!(!cpu.is_empty(), "{name}");
            let builder = MinMaxBuilder::new(&gpu, &compiler, volume.scalar_type()).unwrap();
            let prepared = PreparedVolume::new(&gpu, &builder, &volume).unwrap();
            let extract =
                DirectExtract::with_rule(&gpu, &compiler, volume.scalar_type(), rule).unwrap();
            let capacity = cpu.triangle_count() as u32;
            let lists = TriangleLists::new(&gpu, capacity).unwrap();
            let params = Direct::params(&prepared, iso, &OrbitCamera::default(), 64, 64, capacity);
            gpu.submit("extract", |rec| {
                extract.record(rec, &prepared, &lists, &params)
            })
            .unwrap();
            let stats = extract.read_stats(&gpu).unwrap();
            assert_eq!(stats.triangles as usize, cpu.triangle_count(), "{name}");
            let tris = list_triangles_in_grid(&gpu, &lists, &params);
            assert_same_triangles(&name, &tris, &cpu, 1e-4);
        }
    }
    assert_clean(&gpu);
}

#[test]
fn mesh_shader_triangles_equal_cpu_on_ambiguous_cells() {
    let Some(gpu) = TestGpu::with(&[Need::MeshShaders]) else {
        return;
    };
    let compiler = shaders::compiler();
    let target = RasterTarget::new(&gpu, 64, 64).unwrap();
    for rule in RULES {
        for (volume, iso) in ambiguous_volumes() {
            let name = format!("{} at {iso}, {rule:?}", volume.name());
            let cpu = marching_cubes_with(&volume, iso, rule);
            let direct = Direct::with_rule(&gpu, &compiler, volume.scalar_type(), rule).unwrap();
            let prepared = direct.prepare(&gpu, &volume).unwrap();
            let options = FrameOptions {
                capture_capacity: cpu.triangle_count() as u32 + 64,
                ..Default::default()
            };
            let frame = direct
                .render(
                    &gpu,
                    &prepared,
                    &target,
                    iso,
                    &OrbitCamera::default(),
                    &options,
                )
                .unwrap();
            assert_eq!(
                frame.stats.triangles as usize,
                cpu.triangle_count(),
                "{name}"
            );
            assert_same_triangles(&name, &frame.triangles.unwrap(), &cpu, 1e-5);
        }
    }
    assert_clean(&gpu);
}
