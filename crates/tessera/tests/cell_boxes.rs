//! The cell boxes both paths of `direct` record as they extract a block (the cells that made
//! triangles) and their occlusion culling tests in place of the whole block: they must equal
//! the CPU's, count only at their isovalue, and be forgotten for another volume.

mod common;

use common::{assert_clean, assert_matches_cpu_raster, Need, TestGpu};
use tessera::iso::direct::cell_boxes::{CellBox, CellBoxes};
use tessera::iso::direct::compute::{ComputeTarget, DirectCompute};
use tessera::iso::direct::compute_cull::ComputeCullState;
use tessera::iso::direct::cull::CullState;
use tessera::iso::direct::{Direct, FrameOptions, RasterTarget};
use tessera::shaders;
use tessera::target::Target;
use tessera_data::marching_cubes::{classify_cell, marching_cubes};
use tessera_data::minmax::BLOCK_CELLS;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};
use tessera_gpu::Gpu;

/// Per block, the box of its cells whose case is neither all below nor all above `iso`.
fn cpu_cell_boxes(volume: &Volume, iso: f32) -> Vec<Option<CellBox>> {
    let dims = volume.dims();
    let blocks: [u32; 3] = std::array::from_fn(|a| (dims[a] - 1).div_ceil(BLOCK_CELLS[a]));
    let mut boxes: Vec<Option<CellBox>> = vec![None; blocks.iter().product::<u32>() as usize];
    for z in 0..dims[2] - 1 {
        for y in 0..dims[1] - 1 {
            for x in 0..dims[0] - 1 {
                let case = classify_cell(volume, x, y, z, iso);
                if case == 0 || case == 255 {
                    continue;
                }
                let cell = [x, y, z];
                let block: [u32; 3] = std::array::from_fn(|a| cell[a] / BLOCK_CELLS[a]);
                let local: [u32; 3] = std::array::from_fn(|a| cell[a] % BLOCK_CELLS[a]);
                let b = (block[2] * blocks[1] + block[1]) * blocks[0] + block[0];
                let entry = boxes[b as usize].get_or_insert([local, local]);
                for a in 0..3 {
                    entry[0][a] = entry[0][a].min(local[a]);
                    entry[1][a] = entry[1][a].max(local[a]);
                }
            }
        }
    }
    boxes
}

/// After a frame that extracted every block in view at `iso`: each recorded box equals the
/// CPU's, at least 90 % of the occupied blocks are recorded, at least half the boxes are
/// smaller than a block, and none counts at another isovalue.
fn assert_recorded(gpu: &Gpu, boxes: &CellBoxes, volume: &Volume, iso: f32) {
    let recorded = boxes.read(gpu, iso).unwrap();
    let cpu = cpu_cell_boxes(volume, iso);
    assert_eq!(recorded.len(), cpu.len());
    let occupied = cpu.iter().filter(|b| b.is_some()).count();
    let count = recorded.iter().filter(|b| b.is_some()).count();
    let mut smaller = 0;
    for (b, (gpu_box, cpu_box)) in recorded.iter().zip(&cpu).enumerate() {
        if let Some(gpu_box) = gpu_box {
            assert_eq!(Some(*gpu_box), *cpu_box, "block {b}");
            smaller += usize::from(*gpu_box != [[0; 3], BLOCK_CELLS.map(|c| c - 1)]);
        }
    }
    assert!(
        count * 10 >= occupied * 9,
        "{count} of {occupied} blocks recorded"
    );
    assert!(
        smaller * 2 >= count,
        "only {smaller} of {count} boxes smaller than a block"
    );
    let other = volume.iso_to_texel(IsoValue::Normalized(0.5));
    assert_ne!(other, iso);
    let stale = boxes.read(gpu, other).unwrap();
    assert!(
        stale.iter().all(Option::is_none),
        "boxes count at another isovalue"
    );
}

fn head_and_iso() -> (Volume, f32) {
    let head = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let iso = head.iso_to_texel(IsoValue::Normalized(0.3));
    (head, iso)
}

#[test]
fn the_compute_extraction_records_the_cells_that_made_triangles() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let (head, iso) = head_and_iso();
    let compiler = shaders::compiler();
    let compute = DirectCompute::new(&gpu, &compiler, head.scalar_type()).unwrap();
    let prepared = compute.prepare(&gpu, &head).unwrap();
    let capacity = marching_cubes(&head, iso).triangle_count() as u32 + 16;
    let target = ComputeTarget::new(&gpu, 96, 80, capacity).unwrap();
    let pixels = Target::new(&gpu, 96, 80).unwrap();
    let state = ComputeCullState::new(&gpu, &prepared, &target).unwrap();
    // The first frame after a reset tests every block against an empty pyramid: all those in
    // view are extracted.
    let camera = OrbitCamera::default();
    compute
        .render_culled(&gpu, &prepared, &target, &pixels, &state, iso, &camera)
        .unwrap();
    assert_recorded(&gpu, &state.cell_boxes, &head, iso);
    assert_clean(&gpu);
}

#[test]
fn the_task_shader_records_the_cells_that_made_triangles() {
    let Some(gpu) = TestGpu::with(&[Need::MeshShaders]) else {
        return;
    };
    let (head, iso) = head_and_iso();
    let compiler = shaders::compiler();
    let direct = Direct::new(&gpu, &compiler, head.scalar_type()).unwrap();
    let prepared = direct.prepare(&gpu, &head).unwrap();
    let target = RasterTarget::new(&gpu, 96, 80).unwrap();
    let state = CullState::new(&gpu, &prepared).unwrap();
    // The first frame knows nothing: every region's quad survives the empty depth buffer and
    // every block in view is extracted.
    let options = FrameOptions {
        culling: Some(&state),
        ..Default::default()
    };
    direct
        .render(
            &gpu,
            &prepared,
            &target,
            iso,
            &OrbitCamera::default(),
            &options,
        )
        .unwrap();
    assert_recorded(&gpu, &state.cell_boxes, &head, iso);
    assert_clean(&gpu);
}

/// Two volumes of the same block grid, the isovalue the same.
fn head_and_blobs() -> (Volume, Volume, f32) {
    let head = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let blobs = generate(ProceduralKind::Turbulence, 48, ScalarType::U8).unwrap();
    let iso = head.iso_to_texel(IsoValue::Normalized(0.4));
    (head, blobs, iso)
}

/// A culling state drawn with one volume and then with another: the boxes recorded from the
/// first must not cull the second's blocks.
#[test]
fn compute_culling_forgets_boxes_from_another_volume() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let (head, blobs, iso) = head_and_blobs();
    let compiler = shaders::compiler();
    let compute = DirectCompute::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let capacity = [&head, &blobs]
        .map(|v| marching_cubes(v, iso).triangle_count() as u32 + 16)
        .into_iter()
        .max()
        .unwrap();
    let (w, h) = (96, 80);
    let target = ComputeTarget::new(&gpu, w, h, capacity).unwrap();
    let plain_target = ComputeTarget::new(&gpu, w, h, capacity).unwrap();
    let pixels = Target::new(&gpu, w, h).unwrap();
    let camera = OrbitCamera::default();
    let first = compute.prepare(&gpu, &head).unwrap();
    let state = ComputeCullState::new(&gpu, &first, &target).unwrap();
    for _ in 0..2 {
        compute
            .render_culled(&gpu, &first, &target, &pixels, &state, iso, &camera)
            .unwrap();
    }
    let second = compute.prepare(&gpu, &blobs).unwrap();
    let (plain, _, _) = compute
        .render(&gpu, &second, &plain_target, &pixels, iso, &camera)
        .unwrap();
    let (culled, _, _) = compute
        .render_culled(&gpu, &second, &target, &pixels, &state, iso, &camera)
        .unwrap();
    let diff = culled.compare(&plain, 2);
    assert!(
        diff.fraction_within >= 0.999,
        "{} pixels differ from the unculled frame",
        diff.pixels_outside
    );
    assert_matches_cpu_raster("cull-other-volume", &culled, &blobs, iso, &camera);
    assert_clean(&gpu);
}

#[test]
fn mesh_culling_forgets_boxes_from_another_volume() {
    let Some(gpu) = TestGpu::with(&[Need::MeshShaders]) else {
        return;
    };
    // A pair and view where the first volume's boxes, kept, hide 17 pixels of the second.
    let head = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let lobb = generate(ProceduralKind::MarschnerLobb, 48, ScalarType::U8).unwrap();
    let iso = head.iso_to_texel(IsoValue::Normalized(0.3));
    let compiler = shaders::compiler();
    let direct = Direct::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let target = RasterTarget::new(&gpu, 96, 80).unwrap();
    let camera = common::camera(30.0, 20.0, 2.5);
    let first = direct.prepare(&gpu, &head).unwrap();
    let state = CullState::new(&gpu, &first).unwrap();
    let culled = FrameOptions {
        culling: Some(&state),
        ..Default::default()
    };
    for _ in 0..2 {
        direct
            .render(&gpu, &first, &target, iso, &camera, &culled)
            .unwrap();
    }
    let second = direct.prepare(&gpu, &lobb).unwrap();
    let plain = direct
        .render(
            &gpu,
            &second,
            &target,
            iso,
            &camera,
            &FrameOptions::default(),
        )
        .unwrap();
    // Two frames: the first draws what the quads find, the second starts from it.
    for frame in 0..2 {
        let image = direct
            .render(&gpu, &second, &target, iso, &camera, &culled)
            .unwrap()
            .image;
        let diff = image.compare(&plain.image, 2);
        assert!(
            diff.fraction_within >= 0.999,
            "frame {frame}: {} pixels differ from the unculled frame",
            diff.pixels_outside
        );
        assert_matches_cpu_raster("mesh-cull-other-volume", &image, &lobb, iso, &camera);
    }
    assert_clean(&gpu);
}
