//! Paper C's GPU meshlet extraction (`tessera::iso::meshlets`) against the CPU reference
//! `tessera_data::meshlets::extract_meshlets`: once both are sorted by block and subblock, the
//! descriptors, positions, normals and local indices are equal bit for bit, on both producers
//! (compute, and task/mesh shaders where the device has them) and under both ambiguity rules.

mod common;

use common::volumes::{extraction_volumes, prepare};
use common::{assert_clean, assert_vertices_at_edge_starts, checkerboard, gpu, Need, TestGpu};
use tessera::iso::ablation::Ablation;
use tessera::iso::meshlets::{
    Extraction, ExtractionPath, GpuMeshlets, MeshletCapacity, MeshletCounters, MeshletExtractor,
};
use tessera::iso::PreparedVolume;
use tessera::shaders;
use tessera_data::marching_cubes::AmbiguityRule;
use tessera_data::meshlets::{extract_meshlets, MeshletMesh};
use tessera_data::minmax::{MinMaxOctree, BLOCK_CELLS};
use tessera_data::{ScalarType, Volume};
use tessera_gpu::Gpu;

const RULES: [AmbiguityRule; 2] = [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk];

/// The pipelines for one volume's sample type and `rule`.
fn extractor(
    gpu: &Gpu,
    scalar: ScalarType,
    rule: AmbiguityRule,
    path: ExtractionPath,
) -> MeshletExtractor {
    MeshletExtractor::new(gpu, &shaders::compiler(), scalar, rule, path).unwrap()
}

/// Every output buffer filled with `u32::MAX` (NaN bits for floats), so anything the
/// extraction leaves unwritten shows.
fn poison(gpu: &Gpu, out: &GpuMeshlets) {
    gpu.submit("poison meshlet outputs", |rec| {
        for buffer in [
            &out.meshlets,
            &out.positions,
            &out.normals,
            &out.local_indices,
            &out.block_meshlets,
        ] {
            rec.fill_buffer(buffer, u32::MAX);
        }
    })
    .unwrap();
}

/// Extracts into poisoned buffers of `capacity`, growing them if needed.
fn extract_gpu(
    gpu: &Gpu,
    extractor: &MeshletExtractor,
    prepared: &PreparedVolume,
    iso: f32,
    capacity: MeshletCapacity,
) -> (MeshletMesh, GpuMeshlets, Extraction) {
    let mut out = extractor.buffers(gpu, prepared, capacity).unwrap();
    poison(gpu, &out);
    let extraction = extractor
        .extract_into(gpu, prepared, iso, &mut out)
        .unwrap();
    assert_eq!(extraction.totals, out.totals);
    assert!(extraction.gpu_ms > 0.0, "{extraction:?}");
    (out.read(gpu).unwrap(), out, extraction)
}

/// Room for exactly what the reference needs (each meshlet's triangles rounded up to 4), so
/// the poisoned buffers are the ones written.
fn capacity_for(reference: &MeshletMesh) -> MeshletCapacity {
    let triangles = reference
        .meshlets
        .iter()
        .map(|m| m.triangle_count().next_multiple_of(4))
        .sum();
    MeshletCapacity::new(
        reference.meshlets.len() as u32,
        reference.vertex_count() as u32,
        triangles,
    )
}

/// Both meshes, sorted by block and subblock, equal bit for bit; the GPU's is valid.
fn assert_same_meshlets(what: &str, gpu_mesh: &MeshletMesh, cpu_mesh: &MeshletMesh) {
    gpu_mesh
        .validate()
        .unwrap_or_else(|e| panic!("{what}: GPU meshlets invalid: {e}"));
    let ours = gpu_mesh.in_origin_order().unwrap();
    let reference = cpu_mesh.in_origin_order().unwrap();
    assert_eq!(
        ours.meshlets.len(),
        reference.meshlets.len(),
        "{what}: meshlet count"
    );
    for (k, (a, b)) in ours.meshlets.iter().zip(&reference.meshlets).enumerate() {
        assert_eq!(
            bytemuck::bytes_of(a),
            bytemuck::bytes_of(b),
            "{what}: meshlet {k} differs:\nGPU {a:?}\nCPU {b:?}"
        );
    }
    let bits = |v: &[[f32; 3]]| v.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>();
    let first_difference = |a: &[u32], b: &[u32]| a.iter().zip(b).position(|(x, y)| x != y);
    assert_eq!(
        first_difference(&bits(&ours.positions), &bits(&reference.positions)),
        None,
        "{what}: positions differ (index of the first float)"
    );
    assert_eq!(
        first_difference(&bits(&ours.normals), &bits(&reference.normals)),
        None,
        "{what}: normals differ (index of the first float)"
    );
    assert_eq!(
        ours.local_indices, reference.local_indices,
        "{what}: local indices"
    );
    assert_eq!(ours, reference, "{what}");
}

/// The block list holds exactly the CPU's occupied blocks, and each entry's meshlet range
/// holds that block's meshlets and only them.
fn assert_block_meshlets(what: &str, gpu: &Gpu, volume: &Volume, iso: f32, out: &GpuMeshlets) {
    let mesh = out.read(gpu).unwrap();
    let grid = MinMaxOctree::build(volume);
    let [nx, ny, _] = grid.levels[0].dims;
    let mut expected: Vec<u32> = grid
        .occupied_blocks(iso)
        .map(|b| b[0] + nx * (b[1] + ny * b[2]))
        .collect();
    let entries = out.read_block_meshlets(gpu).unwrap();
    let mut listed: Vec<u32> = entries.iter().map(|e| e.0).collect();
    expected.sort_unstable();
    listed.sort_unstable();
    assert_eq!(listed, expected, "{what}: occupied blocks");
    let mut covered = 0;
    for (block, [first, count]) in entries {
        let b = [block % nx, block / nx % ny, block / (nx * ny)];
        let origin: [u32; 3] = std::array::from_fn(|a| b[a] * BLOCK_CELLS[a]);
        for m in &mesh.meshlets[first as usize..(first + count) as usize] {
            assert_eq!(m.block_origin(), origin, "{what}: block {block}'s meshlets");
        }
        covered += count;
    }
    assert_eq!(
        covered as usize,
        mesh.meshlets.len(),
        "{what}: meshlets of all blocks"
    );
}

fn check_volume(
    gpu: &Gpu,
    extractors: &[MeshletExtractor],
    volume: &Volume,
    iso: f32,
    rule: AmbiguityRule,
) {
    let cpu_mesh = extract_meshlets(volume, iso, rule).unwrap();
    let prepared = prepare(gpu, volume);
    for extractor in extractors {
        let what = format!(
            "{} at {iso}, {rule:?}, {:?}",
            volume.name(),
            extractor.path()
        );
        let (gpu_mesh, out, extraction) =
            extract_gpu(gpu, extractor, &prepared, iso, capacity_for(&cpu_mesh));
        assert_eq!(
            extraction.attempts, 1,
            "{what}: the exact capacity overflowed"
        );
        assert_same_meshlets(&what, &gpu_mesh, &cpu_mesh);
        assert_block_meshlets(&what, gpu, volume, iso, &out);
    }
}

fn extractors(
    gpu: &Gpu,
    scalar: ScalarType,
    rule: AmbiguityRule,
    paths: &[ExtractionPath],
) -> Vec<MeshletExtractor> {
    paths
        .iter()
        .map(|&p| extractor(gpu, scalar, rule, p))
        .collect()
}

#[test]
fn compute_meshlets_equal_cpu_on_procedural_volumes() {
    let gpu = gpu();
    for rule in RULES {
        for (volume, iso) in extraction_volumes() {
            let ex = extractors(&gpu, volume.scalar_type(), rule, &[ExtractionPath::Compute]);
            check_volume(&gpu, &ex, &volume, iso, rule);
        }
    }
    assert_clean(&gpu);
}

#[test]
fn compute_meshlets_split_fully_occupied_blocks() {
    // Every edge crossed: blocks exceed the vertex limit, so quarters and eighths appear.
    let gpu = gpu();
    let volume = checkerboard([19, 10, 9]);
    for rule in RULES {
        let cpu_mesh = extract_meshlets(&volume, 0.5, rule).unwrap();
        assert!(cpu_mesh
            .meshlets
            .iter()
            .any(|m| m.subblock_size() == [2; 3]));
        let ex = extractors(&gpu, ScalarType::F32, rule, &[ExtractionPath::Compute]);
        check_volume(&gpu, &ex, &volume, 0.5, rule);
    }
    assert_clean(&gpu);
}

#[test]
fn compute_meshlets_of_no_surface_are_none() {
    let gpu = gpu();
    let (volume, _) = extraction_volumes().swap_remove(0);
    let ex = extractor(
        &gpu,
        ScalarType::F32,
        AmbiguityRule::default(),
        ExtractionPath::Compute,
    );
    let prepared = prepare(&gpu, &volume);
    // Above every sample, below every sample, and NaN.
    for iso in [2.0, -1.0, f32::NAN] {
        let mut out = ex
            .buffers(&gpu, &prepared, MeshletCapacity::default())
            .unwrap();
        let extraction = ex.extract_into(&gpu, &prepared, iso, &mut out).unwrap();
        assert_eq!(extraction.totals, MeshletCounters::default(), "iso {iso}");
        assert_eq!(extraction.attempts, 1);
        let mesh = out.read(&gpu).unwrap();
        assert_eq!(mesh, MeshletMesh::default(), "iso {iso}");
        assert_eq!(
            mesh,
            extract_meshlets(&volume, iso, AmbiguityRule::default()).unwrap()
        );
    }
    assert_clean(&gpu);
}

#[test]
fn overflowing_buffers_grow_and_give_the_same_meshlets() {
    let gpu = gpu();
    let (volume, iso) = extraction_volumes().swap_remove(1);
    let rule = AmbiguityRule::default();
    let cpu_mesh = extract_meshlets(&volume, iso, rule).unwrap();
    let ex = extractor(&gpu, ScalarType::F32, rule, ExtractionPath::Compute);
    let prepared = prepare(&gpu, &volume);
    let tiny = MeshletCapacity::new(1, 1, 1);
    let (gpu_mesh, out, extraction) = extract_gpu(&gpu, &ex, &prepared, iso, tiny);
    assert_eq!(
        extraction.attempts, 2,
        "one overflow, then the exact totals"
    );
    assert!(out.capacity.meshlets as usize >= cpu_mesh.meshlets.len());
    assert!(out.capacity.vertices as usize >= cpu_mesh.vertex_count());
    assert_same_meshlets("grown from one of each", &gpu_mesh, &cpu_mesh);
    assert_clean(&gpu);
}

#[test]
fn pipelines_refuse_a_volume_of_another_sample_type() {
    let gpu = gpu();
    let ex = extractor(
        &gpu,
        ScalarType::U8,
        AmbiguityRule::default(),
        ExtractionPath::Compute,
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
fn mesh_shader_meshlets_equal_compute_and_cpu() {
    let Some(gpu) = TestGpu::with(&[Need::MeshShaders]) else {
        return;
    };
    // One rule and the float volumes: each further pipeline variant costs llvmpipe minutes
    // to compile, and the analysis and extraction code is the compute path's, which the
    // tests above run under both rules and on integer samples.
    let rule = AmbiguityRule::default();
    let mut cases: Vec<(Volume, f32)> = extraction_volumes()
        .into_iter()
        .filter(|(v, _)| v.scalar_type() == ScalarType::F32)
        .collect();
    cases.insert(0, (checkerboard([19, 10, 9]), 0.5));
    let ex = extractors(
        &gpu,
        ScalarType::F32,
        rule,
        &[ExtractionPath::MeshShaders, ExtractionPath::Compute],
    );
    for (volume, iso) in &cases {
        check_volume(&gpu, &ex, volume, *iso, rule);
    }
    assert_clean(&gpu);
}

#[test]
fn mesh_shader_path_is_refused_or_built_by_capability() {
    let gpu = gpu();
    let made = MeshletExtractor::new(
        &gpu,
        &shaders::compiler(),
        ScalarType::U8,
        AmbiguityRule::default(),
        ExtractionPath::MeshShaders,
    );
    let has = gpu.has(Need::MeshShaders);
    match made {
        Ok(_) => assert!(has),
        Err(e) => {
            assert!(!has, "{e}");
            common::skip(
                "mesh path",
                "the device lacks task/mesh shaders (refusal checked)",
            );
        }
    }
    assert_clean(&gpu);
}

#[test]
fn vertex_ablation_keeps_every_meshlet_and_places_vertices_at_edge_starts() {
    // The ablation times the extraction without its vertex arithmetic; all else must stay.
    let gpu = gpu();
    let (volume, iso) = extraction_volumes().swap_remove(0);
    let rule = AmbiguityRule::default();
    let cpu_mesh = extract_meshlets(&volume, iso, rule).unwrap();
    let prepared = prepare(&gpu, &volume);
    let ablated = MeshletExtractor::ablated(
        &gpu,
        &shaders::compiler(),
        volume.scalar_type(),
        rule,
        ExtractionPath::Compute,
        Ablation::NoVertexArithmetic,
    )
    .unwrap();
    let (gpu_mesh, _, _) = extract_gpu(&gpu, &ablated, &prepared, iso, capacity_for(&cpu_mesh));
    let ours = gpu_mesh.in_origin_order().unwrap();
    let reference = cpu_mesh.in_origin_order().unwrap();
    assert_eq!(ours.local_indices, reference.local_indices);
    let counts = |m: &MeshletMesh| -> Vec<_> {
        m.meshlets
            .iter()
            .map(|m| (m.vertex_count(), m.triangle_count(), m.subblock_origin()))
            .collect()
    };
    assert_eq!(counts(&ours), counts(&reference));
    assert_vertices_at_edge_starts(
        "meshlets",
        &ours.positions,
        &ours.normals,
        Some(&reference.positions),
    );
    assert_clean(&gpu);
}
