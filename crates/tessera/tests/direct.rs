//! Direct isosurface rasterization (paper D) against the CPU marching cubes, on lavapipe or a
//! GPU with mesh shaders. Tests are skipped, visibly, on devices without task/mesh shaders.

mod common;

use tessera::iso::direct::FrameOptions;

use common::{
    assert_clean, assert_matches_cpu_raster, assert_same_triangles, checkerboard, Need, TestGpu,
};
use tessera::iso::direct::compute::{ComputeTarget, DirectCompute};
use tessera::iso::direct::cull::CullState;
use tessera::iso::direct::{Direct, RasterTarget};
use tessera::shaders;
use tessera_data::marching_cubes::marching_cubes;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{IsoValue, OrbitCamera, ScalarType, Volume};

fn mesh_gpu() -> Option<TestGpu> {
    TestGpu::with(&[Need::MeshShaders])
}

#[test]
fn mesh_shader_triangles_equal_cpu_marching_cubes() {
    let Some(gpu) = mesh_gpu() else { return };
    let compiler = shaders::compiler();
    let cases: Vec<(Volume, f32)> = vec![
        (
            generate(ProceduralKind::Sphere, 21, ScalarType::U8).unwrap(),
            0.6,
        ),
        (
            generate(ProceduralKind::HeadPhantom, 26, ScalarType::U8).unwrap(),
            0.3,
        ),
        (
            generate(ProceduralKind::MarschnerLobb, 19, ScalarType::U16).unwrap(),
            0.5,
        ),
        (
            generate(ProceduralKind::Turbulence, 23, ScalarType::F32).unwrap(),
            0.45,
        ),
        (checkerboard([18, 11, 9]), 0.5),
    ];
    let camera = OrbitCamera::default();
    let target = RasterTarget::new(&gpu, 64, 64).unwrap();
    for (volume, fraction) in &cases {
        let iso = volume.iso_to_texel(IsoValue::Normalized(*fraction));
        let cpu = marching_cubes(volume, iso);
        let direct = Direct::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = direct.prepare(&gpu, volume).unwrap();
        let capacity = cpu.triangle_count() as u32 + 64;
        let frame = direct
            .render(
                &gpu,
                &prepared,
                &target,
                iso,
                &camera,
                &FrameOptions {
                    capture_capacity: capacity,
                    ..Default::default()
                },
            )
            .unwrap();
        let tris = frame.triangles.unwrap();
        assert!(!tris.is_empty(), "{}: no triangles", volume.name());
        assert_same_triangles(volume.name(), &tris, &cpu, 1e-5);
        assert_eq!(
            frame.stats.triangles as usize,
            cpu.triangle_count(),
            "{}",
            volume.name()
        );
        assert!(frame.stats.mesh_workgroups > 0);
        assert!(
            frame.stats.vertices
                <= frame.stats.mesh_workgroups * tessera::iso::direct::MAX_VERTICES_PER_LIST,
            "{}: a list exceeded the vertex limit",
            volume.name()
        );
    }
    assert_clean(&gpu);
}

#[test]
fn direct_images_match_cpu_rasterized_marching_cubes() {
    let Some(gpu) = mesh_gpu() else { return };
    let compiler = shaders::compiler();
    let (w, h) = (128, 112);
    let camera = OrbitCamera {
        azimuth_deg: -40.0,
        elevation_deg: 30.0,
        distance: 1.9,
        eye_shift: 0.0,
        eye_rise: 0.0,
        up: Default::default(),
        fov_y_deg: 40.0,
    };
    let target = RasterTarget::new(&gpu, w, h).unwrap();
    let volumes = [
        generate(ProceduralKind::HeadPhantom, 40, ScalarType::U8).unwrap(),
        generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U16).unwrap(),
        generate(ProceduralKind::Turbulence, 29, ScalarType::F32).unwrap(),
    ];
    for volume in &volumes {
        let direct = Direct::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = direct.prepare(&gpu, volume).unwrap();
        for fraction in [0.3f32, 0.6] {
            let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
            let frame = direct
                .render(
                    &gpu,
                    &prepared,
                    &target,
                    iso,
                    &camera,
                    &FrameOptions::default(),
                )
                .unwrap();
            let name = format!("direct-{}-{fraction}", volume.name());
            assert_matches_cpu_raster(&name, &frame.image, volume, iso, &camera);
        }
    }
    assert_clean(&gpu);
}

#[test]
fn occlusion_culling_changes_work_not_images() {
    let Some(gpu) = mesh_gpu() else { return };
    let compiler = shaders::compiler();
    let volume = generate(ProceduralKind::HeadPhantom, 56, ScalarType::U8).unwrap();
    let iso = volume.iso_to_texel(IsoValue::Normalized(0.3));
    let direct = Direct::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let prepared = direct.prepare(&gpu, &volume).unwrap();
    let state = CullState::new(&gpu, &prepared).unwrap();
    let target = RasterTarget::new(&gpu, 96, 80).unwrap();
    let cam = |az: f32| OrbitCamera {
        azimuth_deg: az,
        ..OrbitCamera::default()
    };
    // Still camera for three frames, then a turn that brings hidden regions into view.
    let path = [30.0, 30.0, 30.0, 75.0, 150.0, 150.0];
    let mut drawn_per_frame = Vec::new();
    let mut occupied_regions = 0;
    for (frame, &az) in path.iter().enumerate() {
        let plain = direct
            .render(
                &gpu,
                &prepared,
                &target,
                iso,
                &cam(az),
                &FrameOptions::default(),
            )
            .unwrap();
        let culled = direct
            .render(
                &gpu,
                &prepared,
                &target,
                iso,
                &cam(az),
                &FrameOptions {
                    culling: Some(&state),
                    ..Default::default()
                },
            )
            .unwrap();
        let stats = state.read_stats(&gpu).unwrap();
        let diff = culled.image.compare(&plain.image, 2);
        assert!(
            diff.fraction_within >= 0.999,
            "frame {frame}: culled image differs from the unculled one in {} pixels",
            diff.pixels_outside
        );
        assert!(culled.stats.triangles <= plain.stats.triangles);
        drawn_per_frame.push(stats.blocks_drawn_first + stats.blocks_drawn_new);
        occupied_regions = stats.regions_occupied;
        if frame == 0 {
            assert_eq!(
                stats.blocks_drawn_first, 0,
                "nothing is known before the first frame"
            );
        }
        if frame == 1 || frame == 2 {
            assert_eq!(
                stats.blocks_drawn_new, 0,
                "a still camera finds nothing new"
            );
        }
        if frame == 1 {
            // Frame 0 knew nothing, so everything in view became an occluder; testing against
            // it leaves only what is really visible.
            assert!(stats.blocks_visible < stats.blocks_drawn_first, "{stats:?}");
        }
        if frame == 2 {
            assert!(
                culled.stats.triangles < plain.stats.triangles,
                "frame {frame} culled nothing"
            );
        }
    }
    eprintln!("blocks drawn per frame {drawn_per_frame:?} of {occupied_regions} occupied regions");
    assert_clean(&gpu);
}

#[test]
fn checkerboard_lists_respect_the_vertex_limit() {
    let Some(gpu) = mesh_gpu() else { return };
    let compiler = shaders::compiler();
    let volume = checkerboard([9, 9, 5]); // exactly one fully occupied block
    let direct = Direct::new(&gpu, &compiler, ScalarType::F32).unwrap();
    let prepared = direct.prepare(&gpu, &volume).unwrap();
    let target = RasterTarget::new(&gpu, 32, 32).unwrap();
    let frame = direct
        .render(
            &gpu,
            &prepared,
            &target,
            0.5,
            &OrbitCamera::default(),
            &FrameOptions {
                capture_capacity: 2048,
                ..Default::default()
            },
        )
        .unwrap();
    // 256 cells × 12 vertices, 8 cells per list at 96 vertices: 32 mesh workgroups.
    assert_eq!(frame.stats.mesh_workgroups, 32);
    assert_eq!(frame.stats.vertices, 256 * 12);
    assert_eq!(frame.stats.triangles, 256 * 4);
    assert_clean(&gpu);
}

#[test]
fn isovalue_outside_range_draws_nothing() {
    let Some(gpu) = mesh_gpu() else { return };
    let compiler = shaders::compiler();
    let volume = generate(ProceduralKind::Sphere, 20, ScalarType::U8).unwrap();
    let direct = Direct::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let prepared = direct.prepare(&gpu, &volume).unwrap();
    let target = RasterTarget::new(&gpu, 40, 30).unwrap();
    let frame = direct
        .render(
            &gpu,
            &prepared,
            &target,
            300.0,
            &OrbitCamera::default(),
            &FrameOptions {
                capture_capacity: 16,
                ..Default::default()
            },
        )
        .unwrap();
    assert_eq!(frame.stats.triangles, 0);
    assert_eq!(frame.triangles.unwrap().len(), 0);
    let background = tessera_data::shading::pack_rgba8(tessera_data::shading::BACKGROUND);
    assert!(frame.image.pixels.iter().all(|&p| p == background));
    if gpu.caps().buffer_int64_atomics {
        let compute = DirectCompute::new(&gpu, &compiler, ScalarType::U8).unwrap();
        let target = ComputeTarget::new(&gpu, 40, 30, 16).unwrap();
        let pixels = tessera::target::Target::new(&gpu, 40, 30).unwrap();
        pixels.poison(&gpu, u32::MAX).unwrap();
        let (image, _, stats) = compute
            .render(
                &gpu,
                &prepared,
                &target,
                &pixels,
                300.0,
                &OrbitCamera::default(),
            )
            .unwrap();
        assert_eq!(stats.triangles, 0);
        assert_eq!(
            stats.blocks_classified, 0,
            "the min-max grid rules every block out"
        );
        assert!(image.pixels.iter().all(|&p| p == background));
    }
    assert_clean(&gpu);
}
