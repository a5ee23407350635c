//! Occlusion culling on the compute path of `direct` (max-depth pyramid, two passes): it may
//! change how much is extracted, never the image.

mod common;

use common::{assert_clean, assert_matches_cpu_raster, Need, TestGpu};
use tessera::iso::direct::compute::{ComputeTarget, DirectCompute};
use tessera::iso::direct::compute_cull::{ComputeCullState, ComputeCullStats};
use tessera::raster::hzb::hzb_levels;
use tessera::shaders;
use tessera::target::Target;
use tessera_data::marching_cubes::{classify_cell, marching_cubes};
use tessera_data::minmax::BLOCK_CELLS;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};
use tessera_gpu::Gpu;

fn atomics_gpu() -> Option<TestGpu> {
    TestGpu::with(&[Need::BufferInt64Atomics])
}

/// One camera and isovalue path, culled frame by frame against unculled renders of the same
/// frames (and the CPU reference). Returns (culled triangles, unculled triangles, stats) per
/// frame.
fn run_path(
    gpu: &Gpu,
    name: &str,
    volume: &Volume,
    (w, h): (u32, u32),
    path: &[(f32, OrbitCamera)],
) -> Vec<(u32, u32, ComputeCullStats)> {
    let compiler = shaders::compiler();
    let compute = DirectCompute::new(gpu, &compiler, volume.scalar_type()).unwrap();
    let prepared = compute.prepare(gpu, volume).unwrap();
    let capacity = path
        .iter()
        .map(|(fraction, _)| {
            let iso = volume.iso_to_texel(IsoValue::Normalized(*fraction));
            marching_cubes(volume, iso).triangle_count() as u32 + 16
        })
        .max()
        .unwrap();
    let plain_target = ComputeTarget::new(gpu, w, h, capacity).unwrap();
    let target = ComputeTarget::new(gpu, w, h, capacity).unwrap();
    let pixels = Target::new(gpu, w, h).unwrap();
    let state = ComputeCullState::new(gpu, &prepared, &target).unwrap();
    let mut frames = Vec::new();
    for (frame, (fraction, camera)) in path.iter().enumerate() {
        let iso = volume.iso_to_texel(IsoValue::Normalized(*fraction));
        // Every other frame keeps its depths for the comparison below; the others are emptied
        // by their resolves, so the next frame begins without a fill.
        let kept = frame % 2 == 0;
        plain_target.frame.keep_after_resolve(kept);
        target.frame.keep_after_resolve(kept);
        let (plain, _, plain_stats) = compute
            .render(gpu, &prepared, &plain_target, &pixels, iso, camera)
            .unwrap();
        pixels.poison(gpu, u32::MAX).unwrap();
        let (culled, _, stats) = compute
            .render_culled(gpu, &prepared, &target, &pixels, &state, iso, camera)
            .unwrap();
        eprintln!(
            "{name} frame {frame}: {stats:?}, {} triangles of {}",
            stats.triangles(),
            plain_stats.triangles
        );
        assert!(!culled.pixels.contains(&u32::MAX), "unwritten pixels");
        // Depths do not depend on which of two tying triangles wins, so they must be equal at
        // every pixel: a wrongly culled block shows here even where it would hardly change a
        // colour.
        let depth = |t: &ComputeTarget| -> Vec<u32> {
            t.frame
                .read(gpu)
                .unwrap()
                .iter()
                .map(|v| (v >> 32) as u32)
                .collect()
        };
        if kept {
            let (plain_depth, culled_depth) = (depth(&plain_target), depth(&target));
            let wrong = plain_depth
                .iter()
                .zip(&culled_depth)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(
                wrong, 0,
                "{name} frame {frame}: {wrong} pixels' depths differ"
            );
            let drawn = culled_depth.iter().filter(|&&d| d != u32::MAX).count();
            assert!(drawn > 0, "{name} frame {frame}: no depth kept to compare");
        }
        let diff = culled.compare(&plain, 2);
        if diff.fraction_within < 0.999 {
            let dir = common::out_dir();
            common::write_png(&dir.join(format!("{name}-{frame}-culled.png")), &culled);
            common::write_png(&dir.join(format!("{name}-{frame}-plain.png")), &plain);
            panic!(
                "{name} frame {frame}: the culled image differs from the unculled one in {} \
                 pixels; images in {}",
                diff.pixels_outside,
                dir.display()
            );
        }
        assert_matches_cpu_raster(
            &format!("{name}-frame{frame}"),
            &culled,
            volume,
            iso,
            camera,
        );
        // The two passes draw disjoint sets of occupied blocks.
        assert!(stats.triangles() <= plain_stats.triangles, "{stats:?}");
        assert!(stats.blocks_drawn_new <= stats.blocks_occupied, "{stats:?}");
        assert!(stats.blocks_visible <= stats.blocks_drawn(), "{stats:?}");
        assert_eq!(stats.blocks_occupied, plain_stats.blocks_classified);
        frames.push((stats.triangles(), plain_stats.triangles, stats));
    }
    frames
}

#[test]
fn compute_culling_changes_work_not_images() {
    let Some(gpu) = atomics_gpu() else { return };
    let cam = |az: f32| OrbitCamera {
        azimuth_deg: az,
        ..OrbitCamera::default()
    };
    // Still for three frames, then a turn that brings hidden blocks into view.
    let path = [30.0, 30.0, 30.0, 75.0, 150.0, 150.0].map(|az| (0.3, cam(az)));
    let volume = generate(ProceduralKind::HeadPhantom, 56, ScalarType::U8).unwrap();
    let frames = run_path(&gpu, "compute-cull", &volume, (96, 80), &path);
    let drawn: Vec<_> = frames.iter().map(|f| f.2.blocks_drawn()).collect();
    let triangles: Vec<_> = frames.iter().map(|f| f.0).collect();
    eprintln!(
        "blocks drawn per frame {drawn:?} of {} occupied; triangles {triangles:?} of {}",
        frames[0].2.blocks_occupied, frames[0].1
    );
    let first = frames[0].2;
    assert_eq!(
        first.blocks_drawn_first, 0,
        "nothing is known before frame 0"
    );
    assert_eq!(first.triangles_first, 0);
    assert!(first.blocks_visible > 0);
    for (frame, (culled, plain, stats)) in frames.iter().enumerate() {
        if frame >= 1 && path[frame].1.azimuth_deg == path[frame - 1].1.azimuth_deg {
            // Pass A drew exactly last frame's visible blocks.
            assert_eq!(stats.blocks_drawn_first, frames[frame - 1].2.blocks_visible);
            assert!(stats.blocks_drawn_first > 0);
            assert!(
                culled < plain,
                "frame {frame}: a still camera must extract less ({culled} of {plain})"
            );
        }
    }
    // Turning to 150° uncovers blocks pass A did not have.
    assert!(frames[4].2.blocks_drawn_new > 0, "{:?}", frames[4].2);
    assert_clean(&gpu);
}

#[test]
fn compute_culling_with_the_eye_inside_the_volume() {
    let Some(gpu) = atomics_gpu() else { return };
    // The near plane cuts the volume; blocks behind the eye and off screen take the
    // conservative and the frustum branches of the test.
    let cam = |az: f32, distance: f32| OrbitCamera {
        azimuth_deg: az,
        elevation_deg: 10.0,
        distance,
        ..OrbitCamera::default()
    };
    let path = [
        cam(20.0, 0.6),
        cam(20.0, 0.6),
        cam(60.0, 0.25),
        cam(60.0, 0.25),
        cam(90.0, 0.1),
        cam(60.0, 1.1),
    ]
    .map(|c| (0.3, c));
    let volume = generate(ProceduralKind::HeadPhantom, 56, ScalarType::U8).unwrap();
    let frames = run_path(&gpu, "compute-cull-inside", &volume, (96, 80), &path);
    assert!(frames[1].0 < frames[1].1, "{:?}", frames[1]);
    assert_clean(&gpu);
}

#[test]
fn compute_culling_follows_moves_zooms_and_other_volumes() {
    let Some(gpu) = atomics_gpu() else { return };
    let cam = |az: f32, el: f32, distance: f32| OrbitCamera {
        azimuth_deg: az,
        elevation_deg: el,
        distance,
        ..OrbitCamera::default()
    };
    // Pass A's blocks are last frame's: each move leaves some of them hidden and uncovers
    // blocks next to them.
    let head = generate(ProceduralKind::HeadPhantom, 96, ScalarType::U8).unwrap();
    let path = [
        cam(30.0, 20.0, 1.8),
        cam(60.0, 0.0, 1.5),
        cam(100.0, -30.0, 1.2),
        cam(180.0, 40.0, 1.0),
    ];
    run_path(
        &gpu,
        "cull-head-moves",
        &head,
        (128, 112),
        &path.map(|c| (0.3, c)),
    );
    let blobs = generate(ProceduralKind::Turbulence, 64, ScalarType::U8).unwrap();
    let path = [
        cam(0.0, 0.0, 1.8),
        cam(40.0, 10.0, 1.6),
        cam(80.0, 20.0, 1.4),
        cam(120.0, 30.0, 1.2),
    ];
    run_path(
        &gpu,
        "cull-blobs-moves",
        &blobs,
        (128, 112),
        &path.map(|c| (0.5, c)),
    );
    assert_clean(&gpu);
}

/// The extraction records, per block, the box of the cells that made triangles, which later
/// frames' occlusion test uses in place of the block's whole box: after a frame that drew
/// every block in view, each recorded box equals the box of the block's cells whose case is
/// neither all below nor all above the isovalue, and a box made at one isovalue does not
/// count at another.
#[test]
fn the_extraction_records_the_cells_that_made_triangles() {
    let Some(gpu) = atomics_gpu() else { return };
    let head = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let compiler = shaders::compiler();
    let compute = DirectCompute::new(&gpu, &compiler, head.scalar_type()).unwrap();
    let prepared = compute.prepare(&gpu, &head).unwrap();
    let iso = head.iso_to_texel(IsoValue::Normalized(0.3));
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
    let boxes = state.read_cell_boxes(&gpu, iso).unwrap();
    let dims = head.dims();
    let blocks: [u32; 3] = std::array::from_fn(|a| (dims[a] - 1).div_ceil(BLOCK_CELLS[a]));
    assert_eq!(boxes.len() as u32, blocks.iter().product::<u32>());
    let mut cpu: Vec<Option<[[u32; 3]; 2]>> = vec![None; boxes.len()];
    for z in 0..dims[2] - 1 {
        for y in 0..dims[1] - 1 {
            for x in 0..dims[0] - 1 {
                let case = classify_cell(&head, x, y, z, iso);
                if case == 0 || case == 255 {
                    continue;
                }
                let cell = [x, y, z];
                let block: [u32; 3] = std::array::from_fn(|a| cell[a] / BLOCK_CELLS[a]);
                let local: [u32; 3] = std::array::from_fn(|a| cell[a] % BLOCK_CELLS[a]);
                let b = (block[2] * blocks[1] + block[1]) * blocks[0] + block[0];
                let entry = cpu[b as usize].get_or_insert([local, local]);
                for a in 0..3 {
                    entry[0][a] = entry[0][a].min(local[a]);
                    entry[1][a] = entry[1][a].max(local[a]);
                }
            }
        }
    }
    let occupied = cpu.iter().filter(|b| b.is_some()).count();
    let recorded = boxes.iter().filter(|b| b.is_some()).count();
    let mut smaller = 0;
    for (b, (gpu_box, cpu_box)) in boxes.iter().zip(&cpu).enumerate() {
        if let Some(gpu_box) = gpu_box {
            assert_eq!(Some(*gpu_box), *cpu_box, "block {b}");
            smaller += usize::from(*gpu_box != [[0; 3], BLOCK_CELLS.map(|c| c - 1)]);
        }
    }
    assert!(
        recorded * 10 >= occupied * 9,
        "{recorded} of {occupied} blocks recorded"
    );
    assert!(
        smaller * 2 >= recorded,
        "only {smaller} of {recorded} boxes smaller than a block"
    );
    // Made at another isovalue: none counts.
    let other = head.iso_to_texel(IsoValue::Normalized(0.5));
    let stale = state.read_cell_boxes(&gpu, other).unwrap();
    assert!(stale.iter().all(Option::is_none));
    assert_clean(&gpu);
}

/// A culling state drawn with one volume and then with another of the same block grid at the
/// same isovalue: the boxes recorded from the first must not cull the second's blocks.
#[test]
fn boxes_from_another_volume_are_forgotten() {
    let Some(gpu) = atomics_gpu() else { return };
    let head = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let blobs = generate(ProceduralKind::Turbulence, 48, ScalarType::U8).unwrap();
    let compiler = shaders::compiler();
    let compute = DirectCompute::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let iso = head.iso_to_texel(IsoValue::Normalized(0.4));
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
fn compute_culling_follows_isovalue_changes() {
    let Some(gpu) = atomics_gpu() else { return };
    // A still camera, a new isovalue each frame: last frame's visible blocks may now be empty
    // or hold surfaces behind new ones.
    let head = generate(ProceduralKind::HeadPhantom, 96, ScalarType::U8).unwrap();
    let camera = OrbitCamera {
        azimuth_deg: 30.0,
        elevation_deg: 20.0,
        ..OrbitCamera::default()
    };
    let path = [0.3, 0.6, 0.45, 0.2, 0.7].map(|f| (f, camera));
    run_path(&gpu, "cull-iso-changes", &head, (128, 112), &path);
    assert_clean(&gpu);
}

#[test]
fn reset_forgets_what_was_seen() {
    let Some(gpu) = atomics_gpu() else { return };
    let compiler = shaders::compiler();
    let volume = generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U8).unwrap();
    let iso = volume.iso_to_texel(IsoValue::Normalized(0.5));
    let compute = DirectCompute::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let prepared = compute.prepare(&gpu, &volume).unwrap();
    let capacity = marching_cubes(&volume, iso).triangle_count() as u32;
    let target = ComputeTarget::new(&gpu, 64, 48, capacity).unwrap();
    let pixels = Target::new(&gpu, 64, 48).unwrap();
    let state = ComputeCullState::new(&gpu, &prepared, &target).unwrap();
    let camera = OrbitCamera::default();
    let mut images = Vec::new();
    for reset in [false, false, true] {
        if reset {
            state.reset(&gpu).unwrap();
        }
        let (image, _, stats) = compute
            .render_culled(&gpu, &prepared, &target, &pixels, &state, iso, &camera)
            .unwrap();
        assert_eq!(stats.blocks_drawn_first == 0, images.is_empty() || reset);
        images.push(image);
    }
    assert!(images[2].compare(&images[0], 2).fraction_within >= 0.999);
    assert!(images[1].compare(&images[0], 2).fraction_within >= 0.999);
    // A state for another frame size is refused.
    let other = ComputeTarget::new(&gpu, 32, 48, capacity).unwrap();
    let other_pixels = Target::new(&gpu, 32, 48).unwrap();
    assert!(compute
        .render_culled(&gpu, &prepared, &other, &other_pixels, &state, iso, &camera)
        .is_err());
    assert_clean(&gpu);
}

#[test]
fn pyramid_levels_end_at_one_texel() {
    assert_eq!(hzb_levels(1, 1), vec![[1, 1]]);
    assert_eq!(
        hzb_levels(96, 80),
        vec![[48, 40], [24, 20], [12, 10], [6, 5], [3, 3], [2, 2], [1, 1]]
    );
    assert_eq!(hzb_levels(5, 1), vec![[3, 1], [2, 1], [1, 1]]);
}
