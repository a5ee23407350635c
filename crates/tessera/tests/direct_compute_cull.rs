//! Occlusion culling on the compute path of `direct` (max-depth pyramid, two passes): it may
//! change how much is extracted, never the image.

mod common;

use common::{assert_clean, assert_matches_cpu_raster, Need, TestGpu};
use tessera::iso::direct::compute::{ComputeTarget, DirectCompute};
use tessera::iso::direct::compute_cull::{ComputeCullState, ComputeCullStats};
use tessera::iso::direct::Direct;
use tessera::iso::PreparedVolume;
use tessera::raster::hzb::hzb_levels;
use tessera::shaders;
use tessera::target::Target;
use tessera_data::marching_cubes::marching_cubes;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{IsoValue, OrbitCamera, RgbaImage, ScalarType, Volume};
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
        // Both passes leave out what no pixel of a closed surface shows, as the plain frame does.
        let params = Direct::params(&prepared, iso, camera, w, h, capacity);
        let hidden = Direct::hidden_winding(&prepared, &params);
        assert_eq!(
            target.frame.hidden_winding(),
            hidden,
            "{name} frame {frame}"
        );
        assert_eq!(plain_target.frame.hidden_winding(), hidden);
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
    // Against the first frame's empty pyramid no cell is hidden.
    assert_eq!(first.triangles_new_hidden, 0);
    for (frame, (culled, plain, stats)) in frames.iter().enumerate() {
        if frame >= 1 && path[frame].1.azimuth_deg == path[frame - 1].1.azimuth_deg {
            // Pass A drew exactly last frame's visible blocks.
            assert_eq!(stats.blocks_drawn_first, frames[frame - 1].2.blocks_visible);
            assert!(stats.blocks_drawn_first > 0);
            assert!(
                culled < plain,
                "frame {frame}: a still camera must extract less ({culled} of {plain})"
            );
            // Most cells of the blocks pass B draws in a still frame lie behind pass A's
            // surface, and make no triangles (the depths above show none was visible).
            assert!(
                stats.triangles_new_hidden > stats.triangles_new,
                "frame {frame}: {stats:?}"
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

/// One volume's culled frames: the pipelines, the prepared volume, a target whose lists hold
/// its whole surface at `iso`, pixels and a culling state, seen from the default camera.
struct Culling {
    compute: DirectCompute,
    prepared: PreparedVolume,
    iso: f32,
    capacity: u32,
    target: ComputeTarget,
    pixels: Target,
    state: ComputeCullState,
    camera: OrbitCamera,
}

impl Culling {
    fn new(gpu: &Gpu, volume: &Volume, fraction: f32, (w, h): (u32, u32)) -> Culling {
        let compute = DirectCompute::new(gpu, &shaders::compiler(), volume.scalar_type()).unwrap();
        let prepared = compute.prepare(gpu, volume).unwrap();
        let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
        let capacity = marching_cubes(volume, iso).triangle_count() as u32;
        let target = ComputeTarget::new(gpu, w, h, capacity).unwrap();
        let pixels = Target::new(gpu, w, h).unwrap();
        let state = ComputeCullState::new(gpu, &prepared, &target).unwrap();
        Culling {
            compute,
            prepared,
            iso,
            capacity,
            target,
            pixels,
            state,
            camera: OrbitCamera::default(),
        }
    }

    /// A culled frame with `state` (this one's, or another made for its target).
    fn culled(&self, gpu: &Gpu, state: &ComputeCullState) -> (RgbaImage, ComputeCullStats) {
        self.pixels.poison(gpu, u32::MAX).unwrap();
        let (image, _, stats) = self
            .compute
            .render_culled(
                gpu,
                &self.prepared,
                &self.target,
                &self.pixels,
                state,
                self.iso,
                &self.camera,
            )
            .unwrap();
        (image, stats)
    }
}

#[test]
fn reset_forgets_what_was_seen() {
    let Some(gpu) = atomics_gpu() else { return };
    let volume = generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U8).unwrap();
    let c = Culling::new(&gpu, &volume, 0.5, (64, 48));
    let mut images = Vec::new();
    for reset in [false, false, true] {
        if reset {
            c.state.reset(&gpu).unwrap();
        }
        let (image, stats) = c.culled(&gpu, &c.state);
        assert_eq!(stats.blocks_drawn_first == 0, images.is_empty() || reset);
        images.push(image);
    }
    assert!(images[2].compare(&images[0], 2).fraction_within >= 0.999);
    assert!(images[1].compare(&images[0], 2).fraction_within >= 0.999);
    // A state for another frame size is refused.
    let other = ComputeTarget::new(&gpu, 32, 48, c.capacity).unwrap();
    let other_pixels = Target::new(&gpu, 32, 48).unwrap();
    assert!(c
        .compute
        .render_culled(
            &gpu,
            &c.prepared,
            &other,
            &other_pixels,
            &c.state,
            c.iso,
            &c.camera
        )
        .is_err());
    assert_clean(&gpu);
}

/// A culled frame that follows its own state's frame into the same target relies on that
/// frame's finishing pass to have emptied its counts and lists; one that follows another frame
/// begun in the target (unculled, or another state's) empties them itself. Either way a still
/// view gives the same counts and image frame after frame.
#[test]
fn culled_frames_after_other_frames_into_their_target() {
    let Some(gpu) = atomics_gpu() else { return };
    let volume = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let c = Culling::new(&gpu, &volume, 0.3, (80, 64));
    let other_state = ComputeCullState::new(&gpu, &c.prepared, &c.target).unwrap();
    for _ in 0..2 {
        c.culled(&gpu, &c.state);
    }
    let (settled_image, settled) = c.culled(&gpu, &c.state);
    assert!(
        settled.blocks_drawn_first > 0 && settled.triangles_first > 0,
        "{settled:?}"
    );
    let unculled = |camera: &OrbitCamera| {
        let rendered = c
            .compute
            .render(&gpu, &c.prepared, &c.target, &c.pixels, c.iso, camera);
        rendered.unwrap().0
    };
    let plain = unculled(&c.camera);
    assert!(settled_image.compare(&plain, 2).fraction_within >= 0.999);
    // After an unculled frame of another view, whose counts (and triangles) it leaves in the
    // target, and after another state's frames into the target.
    let turned = OrbitCamera {
        azimuth_deg: c.camera.azimuth_deg + 50.0,
        ..c.camera
    };
    assert!(unculled(&turned).compare(&plain, 2).fraction_within < 0.9);
    let (image, stats) = c.culled(&gpu, &c.state);
    assert_eq!(stats, settled, "after an unculled frame");
    assert!(image.compare(&plain, 2).fraction_within >= 0.999);
    for _ in 0..2 {
        c.culled(&gpu, &other_state);
    }
    for what in ["after another state's frames", "after its own frame"] {
        let (image, stats) = c.culled(&gpu, &c.state);
        assert_eq!(stats, settled, "{what}");
        assert!(image.compare(&plain, 2).fraction_within >= 0.999, "{what}");
    }
    assert_clean(&gpu);
}

#[test]
fn pass_a_extraction_alone_and_its_ablations() {
    use tessera::iso::ablation::Ablation;
    use tessera::iso::direct::compute_cull::{measured_list_extraction, FirstExtractionWay};
    use tessera::raster::RasterCounts;
    use tessera_gpu::Timer;
    let Some(gpu) = atomics_gpu() else { return };
    let compiler = shaders::compiler();
    let volume = generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap();
    let (w, h) = (80, 64);
    let c = Culling::new(&gpu, &volume, 0.3, (w, h));
    c.culled(&gpu, &c.state);
    let (_, settled) = c.culled(&gpu, &c.state);
    assert!(settled.triangles_first > 100, "{settled:?}");
    let params = Direct::params(&c.prepared, c.iso, &c.camera, w, h, c.capacity);
    let mut timer = Timer::new(&gpu, 1).unwrap();
    let mut extract_way = |way: FirstExtractionWay| -> (u32, Vec<Vec<u32>>) {
        let pipeline = measured_list_extraction(&gpu, &compiler, ScalarType::U8, way).unwrap();
        timer.reset(&gpu);
        let mut recorded = Ok(());
        gpu.submit("pass A alone", |rec| {
            recorded = c.compute.record_first_extraction(
                rec,
                (&mut timer, "extraction"),
                &pipeline,
                &c.prepared,
                &c.target,
                &params,
                &c.state,
            );
        })
        .unwrap();
        recorded.unwrap();
        let counts: RasterCounts =
            bytemuck::pod_read_unaligned(&gpu.read_buffer(&c.target.lists.counts).unwrap()[..16]);
        // Blocks reserve their slots in whichever order their workgroups run: compare the
        // triangles as a set, each as its 12 words.
        let made = counts.triangle_count as usize * 48;
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(
            &gpu.read_buffer(&c.target.lists.triangles).unwrap()[..made],
        );
        let mut triangles: Vec<Vec<u32>> = words.chunks(12).map(<[u32]>::to_vec).collect();
        triangles.sort_unstable();
        (counts.triangle_count, triangles)
    };
    let mut extract = |ablation: Ablation| {
        extract_way(FirstExtractionWay {
            ablation,
            spread_corners: false,
        })
    };
    let (whole, whole_triangles) = extract(Ablation::None);
    assert_eq!(whole, settled.triangles_first);
    let (standing_in, stand_in_triangles) = extract(Ablation::NoVertexArithmetic);
    assert_eq!(standing_in, whole);
    assert_ne!(stand_in_triangles, whole_triangles);
    assert_eq!(extract(Ablation::AnalysisOnly).0, 0);
    assert_eq!(extract(Ablation::SamplesOnly).0, 0);
    // Each corner made by its own invocation: the same triangles in the same slots.
    let spread = extract_way(FirstExtractionWay {
        ablation: Ablation::None,
        spread_corners: true,
    });
    assert!(spread == (whole, whole_triangles.clone()), "corners spread");
    let (_, after) = c.culled(&gpu, &c.state);
    assert_eq!(after, settled, "the next frame");
    // A state made for another frame size is refused, with nothing recorded.
    let other = ComputeTarget::new(&gpu, w / 2, h, c.capacity).unwrap();
    let pipeline = measured_list_extraction(
        &gpu,
        &compiler,
        ScalarType::U8,
        FirstExtractionWay {
            ablation: Ablation::None,
            spread_corners: false,
        },
    )
    .unwrap();
    let mut refused = Ok(());
    gpu.submit("pass A alone, wrong state", |rec| {
        refused = c.compute.record_first_extraction(
            rec,
            (&mut timer, "extraction"),
            &pipeline,
            &c.prepared,
            &other,
            &params,
            &c.state,
        );
    })
    .unwrap();
    let message = refused.unwrap_err().to_string();
    assert!(
        message.contains("another frame size or volume"),
        "{message}"
    );
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
