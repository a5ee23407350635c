//! Parallel Marching Blocks on the GPU (`tessera::iso::pmb`) against the CPU marching cubes
//! (`tessera_data::marching_cubes`), for every block size and both ambiguity rules: the
//! triangles are the same multiset, each block's vertices are unique and its indices in
//! range, welding the blocks gives marching cubes' vertices and normals bit for bit, and each
//! block holds the triangles of its own cells. Outputs are poisoned first, so anything left
//! unwritten shows.

mod common;

use common::volumes::{extraction_volumes, poison_pmb as poison, prepare};
use common::{
    assert_clean, assert_same_triangles, assert_vertices_at_edge_starts, checkerboard, gpu,
};
use glam::Vec3;
use std::collections::BTreeMap;
use tessera::iso::ablation::Ablation;
use tessera::iso::pmb::{
    GpuPmb, PmbBlockSize, PmbCapacity, PmbCounters, PmbExtractor, PmbInvocations, PmbMesh,
    PmbTuning,
};
use tessera::iso::PreparedVolume;
use tessera::shaders;
use tessera_data::marching_cubes::{marching_cubes_with, AmbiguityRule};
use tessera_data::mc_tables::{mc_tables, CORNER_OFFSETS};
use tessera_data::mesh::TriangleMesh;
use tessera_data::minmax::{MinMaxOctree, BLOCK_CELLS};
use tessera_data::{ScalarType, Volume};
use tessera_gpu::Gpu;

/// Positions are compared in grid units.
const TOLERANCE: f32 = 1e-5;

fn extractor(
    gpu: &Gpu,
    scalar: ScalarType,
    rule: AmbiguityRule,
    size: PmbBlockSize,
) -> PmbExtractor {
    PmbExtractor::new(gpu, &shaders::compiler(), scalar, rule, size).unwrap()
}

/// An extractor with one invocation per sample of the block's box (Liu et al.'s layout).
fn one_per_sample(gpu: &Gpu, rule: AmbiguityRule, size: PmbBlockSize) -> PmbExtractor {
    let tuning = PmbTuning {
        invocations: PmbInvocations::OnePerSample,
        ..PmbTuning::default()
    };
    PmbExtractor::tuned(
        gpu,
        &shaders::compiler(),
        ScalarType::F32,
        rule,
        size,
        tuning,
    )
    .unwrap()
}

/// Extracts into poisoned buffers of `capacity`, growing them if needed.
fn extract_gpu(
    gpu: &Gpu,
    extractor: &PmbExtractor,
    prepared: &PreparedVolume,
    iso: f32,
    capacity: PmbCapacity,
) -> (PmbMesh, GpuPmb) {
    let mut out = extractor.buffers(gpu, prepared, capacity).unwrap();
    poison(gpu, &out);
    extractor
        .extract_into(gpu, prepared, iso, &mut out)
        .unwrap();
    (out.read(gpu).unwrap(), out)
}

/// Triangles per PMB block, counted cell by cell as marching cubes cuts the cells.
fn cpu_block_triangles(
    volume: &Volume,
    iso: f32,
    rule: AmbiguityRule,
    size: PmbBlockSize,
) -> BTreeMap<[u32; 3], u32> {
    let tables = mc_tables();
    let [nx, ny, nz] = volume.dims();
    let cells = size.cells();
    let mut blocks = BTreeMap::new();
    for z in 0..nz - 1 {
        for y in 0..ny - 1 {
            for x in 0..nx - 1 {
                let values = CORNER_OFFSETS.map(|o| {
                    volume.texel(
                        x + u32::from(o[0]),
                        y + u32::from(o[1]),
                        z + u32::from(o[2]),
                    )
                });
                let case = (0..8).fold(0u8, |c, i| c | u8::from(values[i] < iso) << i);
                let row = tables.row(case, rule.joined_faces(case, &values, iso));
                let count = u32::from(tables.tri_count[row]);
                if count > 0 {
                    let block = [x / cells[0], y / cells[1], z / cells[2]];
                    *blocks.entry(block).or_insert(0) += count;
                }
            }
        }
    }
    blocks
}

/// The PMB blocks (ids, x fastest) that overlap a level-0 min-max block whose range holds
/// `iso`, sorted.
fn cpu_occupied(volume: &Volume, iso: f32, size: PmbBlockSize) -> Vec<u32> {
    let level = &MinMaxOctree::build(volume).levels[0];
    let [gx, gy, gz] = size.grid(volume.dims());
    let cells = size.cells();
    let holds = |n: [u32; 3]| {
        let [lo, hi] = level.nodes[(n[0] + level.dims[0] * (n[1] + level.dims[1] * n[2])) as usize];
        lo <= iso && iso <= hi
    };
    let mut occupied = Vec::new();
    for z in 0..gz {
        for y in 0..gy {
            for x in 0..gx {
                let b = [x, y, z];
                let first: [u32; 3] = std::array::from_fn(|a| b[a] * cells[a] / BLOCK_CELLS[a]);
                let last: [u32; 3] = std::array::from_fn(|a| {
                    (((b[a] + 1) * cells[a] - 1) / BLOCK_CELLS[a]).min(level.dims[a] - 1)
                });
                let any = (first[2]..=last[2]).any(|nz| {
                    (first[1]..=last[1])
                        .any(|ny| (first[0]..=last[0]).any(|nx| holds([nx, ny, nz])))
                });
                if any {
                    occupied.push(x + gx * (y + gy * z));
                }
            }
        }
    }
    occupied
}

/// Positions and normals as bits, paired and sorted: the vertex multiset.
fn vertex_bits(mesh: &TriangleMesh) -> Vec<([u32; 3], [u32; 3])> {
    let mut v: Vec<_> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .map(|(p, n)| {
            (
                p.to_array().map(f32::to_bits),
                n.to_array().map(f32::to_bits),
            )
        })
        .collect();
    v.sort_unstable();
    v
}

/// Holds the GPU's PMB mesh of `volume` at `iso` to marching cubes; returns it.
fn check_volume(
    gpu: &Gpu,
    ex: &PmbExtractor,
    volume: &Volume,
    iso: f32,
    rule: AmbiguityRule,
) -> PmbMesh {
    let size = ex.block_size();
    let what = format!("{} at {iso}, {rule:?}, {}", volume.name(), size.name());
    let cpu = marching_cubes_with(volume, iso, rule);
    let prepared = prepare(gpu, volume);
    let (mesh, out) = extract_gpu(gpu, ex, &prepared, iso, PmbCapacity::default());
    mesh.validate()
        .unwrap_or_else(|e| panic!("{what}: GPU mesh invalid: {e}"));
    assert_eq!(mesh.block_size, size.cells(), "{what}");
    assert!(cpu.triangle_count() > 0, "{what}: the test needs a surface");
    let triangles: Vec<[Vec3; 3]> = mesh.triangles().map(|t| t.map(Vec3::from)).collect();
    assert_same_triangles(&what, &triangles, &cpu, TOLERANCE);
    assert_eq!(
        vertex_bits(&mesh.welded()),
        vertex_bits(&cpu),
        "{what}: welded vertices"
    );
    let blocks: BTreeMap<[u32; 3], u32> = mesh
        .blocks
        .iter()
        .map(|b| (b.block, b.triangle_count))
        .collect();
    assert_eq!(
        blocks,
        cpu_block_triangles(volume, iso, rule, size),
        "{what}: triangles per block"
    );
    let mut occupied = out.read_occupied(gpu).unwrap();
    occupied.sort_unstable();
    assert_eq!(
        occupied,
        cpu_occupied(volume, iso, size),
        "{what}: occupied blocks"
    );
    mesh
}

/// A checkerboard's blocks that lie whole inside the volume hold a vertex on every edge of
/// their box and four triangles per cell; there is at least one.
fn assert_whole_blocks_full(mesh: &PmbMesh, volume: &Volume, size: PmbBlockSize) {
    let [x, y, z] = size.cells();
    let box_edges = x * (y + 1) * (z + 1) + (x + 1) * y * (z + 1) + (x + 1) * (y + 1) * z;
    let whole: Vec<_> = mesh
        .blocks
        .iter()
        .filter(|b| (0..3).all(|a| (b.block[a] + 1) * size.cells()[a] < volume.dims()[a]))
        .collect();
    assert!(!whole.is_empty(), "{}: no whole block", size.name());
    for b in whole {
        assert_eq!(
            b.vertex_count,
            box_edges,
            "{} block {:?}",
            size.name(),
            b.block
        );
        assert_eq!(
            b.triangle_count,
            4 * x * y * z,
            "{} block {:?}",
            size.name(),
            b.block
        );
    }
}

#[test]
fn pmb_triangles_equal_marching_cubes_for_every_block_size() {
    // The float volumes, and a checkerboard of 17×10×9 cells whose every edge is crossed, so
    // each size has fully occupied blocks beside partial ones.
    let gpu = gpu();
    let mut cases: Vec<(Volume, f32)> = extraction_volumes()
        .into_iter()
        .filter(|(v, _)| v.scalar_type() == ScalarType::F32)
        .collect();
    let full = cases.len();
    cases.push((checkerboard([18, 11, 10]), 0.5));
    // The rule picks table rows the same way for every block size, so VTK's is held to the
    // reference at one size: each pipeline variant costs llvmpipe a minute or more to compile.
    let runs = [
        (AmbiguityRule::AsymptoticDecider, &PmbBlockSize::ALL[..]),
        (AmbiguityRule::Vtk, &[PmbBlockSize::B884][..]),
    ];
    for (rule, sizes) in runs {
        for &size in sizes {
            let mut extractors = vec![extractor(&gpu, ScalarType::F32, rule, size)];
            // Both layouts of the invocations, at every size, under one rule.
            if rule == AmbiguityRule::AsymptoticDecider {
                extractors.push(one_per_sample(&gpu, rule, size));
            }
            for ex in &extractors {
                for (k, (volume, iso)) in cases.iter().enumerate() {
                    let mesh = check_volume(&gpu, ex, volume, *iso, rule);
                    if k == full {
                        assert_whole_blocks_full(&mesh, volume, size);
                    }
                }
            }
        }
    }
    assert_clean(&gpu);
}

#[test]
fn pmb_of_integer_samples_equals_marching_cubes() {
    // One pipeline variant: each costs llvmpipe a minute or more to compile, and the sample
    // type changes only how texels are fetched.
    let gpu = gpu();
    let rule = AmbiguityRule::default();
    let ex = extractor(&gpu, ScalarType::U8, rule, PmbBlockSize::B844);
    for (volume, iso) in extraction_volumes()
        .iter()
        .filter(|(v, _)| v.scalar_type() == ScalarType::U8)
    {
        check_volume(&gpu, &ex, volume, *iso, rule);
    }
    assert_clean(&gpu);
}

#[test]
fn no_surface_gives_no_blocks() {
    let gpu = gpu();
    let (volume, _) = extraction_volumes().swap_remove(0);
    let prepared = prepare(&gpu, &volume);
    let ex = extractor(
        &gpu,
        ScalarType::F32,
        AmbiguityRule::default(),
        PmbBlockSize::B844,
    );
    // Above every sample, below every sample, and NaN.
    for iso in [2.0, -1.0, f32::NAN] {
        let (mesh, out) = extract_gpu(&gpu, &ex, &prepared, iso, PmbCapacity::default());
        assert_eq!(out.totals, PmbCounters::default(), "iso {iso}");
        assert_eq!(
            mesh,
            PmbMesh {
                block_size: PmbBlockSize::B844.cells(),
                ..PmbMesh::default()
            },
            "iso {iso}"
        );
        assert!(out.read_occupied(&gpu).unwrap().is_empty(), "iso {iso}");
    }
    assert_clean(&gpu);
}

#[test]
fn overflowing_buffers_grow_and_give_the_same_surface() {
    let gpu = gpu();
    let (volume, iso) = extraction_volumes().swap_remove(1);
    let rule = AmbiguityRule::default();
    let cpu = marching_cubes_with(&volume, iso, rule);
    let ex = extractor(&gpu, ScalarType::F32, rule, PmbBlockSize::B444);
    let prepared = prepare(&gpu, &volume);
    let tiny = PmbCapacity::new(1, 1);
    let (mesh, out) = extract_gpu(&gpu, &ex, &prepared, iso, tiny);
    assert_ne!(out.capacity, tiny, "the buffers grew");
    assert!(out.capacity.vertices >= out.totals.vertices);
    assert_eq!(out.totals.triangles as usize, cpu.triangle_count());
    mesh.validate().unwrap();
    let triangles: Vec<[Vec3; 3]> = mesh.triangles().map(|t| t.map(Vec3::from)).collect();
    assert_same_triangles("grown from one of each", &triangles, &cpu, TOLERANCE);
    assert_clean(&gpu);
}

#[test]
fn pipelines_refuse_a_volume_of_another_sample_type() {
    let gpu = gpu();
    let ex = extractor(
        &gpu,
        ScalarType::U8,
        AmbiguityRule::default(),
        PmbBlockSize::B884,
    );
    let (volume, iso) = extraction_volumes().swap_remove(0);
    let prepared = prepare(&gpu, &volume);
    let error = ex.extract(&gpu, &prepared, iso).unwrap_err().to_string();
    assert!(
        error.contains("uint8") && error.contains("float32"),
        "{error}"
    );
    assert_clean(&gpu);
}

#[test]
fn vertex_ablation_keeps_the_counts_and_places_vertices_at_edge_starts() {
    let gpu = gpu();
    let (volume, iso) = extraction_volumes().swap_remove(0);
    let rule = AmbiguityRule::default();
    let prepared = prepare(&gpu, &volume);
    let size = PmbBlockSize::B844;
    let whole = extractor(&gpu, ScalarType::F32, rule, size);
    let tuning = PmbTuning {
        ablation: Ablation::NoVertexArithmetic,
        ..PmbTuning::default()
    };
    let ablated = PmbExtractor::tuned(
        &gpu,
        &shaders::compiler(),
        ScalarType::F32,
        rule,
        size,
        tuning,
    )
    .unwrap();
    let (_, exact) = extract_gpu(&gpu, &whole, &prepared, iso, PmbCapacity::default());
    let (mesh, out) = extract_gpu(&gpu, &ablated, &prepared, iso, PmbCapacity::default());
    assert_eq!(out.totals, exact.totals);
    assert_vertices_at_edge_starts("PMB", &mesh.positions, &mesh.normals, None);
    assert_clean(&gpu);
}
