//! `direct`'s compute path with each extraction workgroup drawing its own triangles
//! (`DirectRaster::InExtraction`), the rasterizer reading each pixel before its atomic
//! (`RasterVariant::ReadBeforeAtomic`) and subgroups walking their triangles together
//! (`RasterVariant::SubgroupWalk`), each way and combined, draw the frames the raster pass after the extraction
//! draws: the same depth at every pixel and the same image, culled or not, with the near plane
//! cutting the volume, with the hidden side left out or drawn, and on open surfaces. The
//! rasterizer's ablations draw nothing but mark the tiles (all but the one that draws no
//! triangle).

mod common;

use common::{assert_clean, Need, TestGpu};
use tessera::iso::direct::compute::{ComputeTarget, DirectCompute, DirectRaster};
use tessera::iso::direct::compute_cull::{ComputeCullState, ComputeCullStats};
use tessera::iso::{HiddenSide, PreparedVolume};
use tessera::raster::RasterVariant;
use tessera::shaders;
use tessera::target::Target;
use tessera_data::marching_cubes::marching_cubes;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{IsoValue, OrbitCamera, RgbaImage, ScalarType, Volume};
use tessera_gpu::Gpu;

/// What one frame left: its image, the depth bits at every pixel, and what it counted.
struct Drawn {
    image: RgbaImage,
    depths: Vec<u32>,
    triangles: u32,
    culling: Option<ComputeCullStats>,
}

/// One way of drawing: its pipelines, the volume prepared for them, and its buffers.
struct Way {
    compute: DirectCompute,
    prepared: PreparedVolume,
    target: ComputeTarget,
    state: ComputeCullState,
    pixels: Target,
}

impl Way {
    fn new(
        gpu: &Gpu,
        volume: &Volume,
        (raster, variant): (DirectRaster, RasterVariant),
        size: (u32, u32),
        capacity: u32,
    ) -> Way {
        let compiler = shaders::compiler();
        let compute =
            DirectCompute::for_measuring(gpu, &compiler, volume.scalar_type(), raster, variant)
                .unwrap();
        assert_eq!(compute.raster(), raster);
        let prepared = compute.prepare(gpu, volume).unwrap();
        let target = ComputeTarget::new(gpu, size.0, size.1, capacity).unwrap();
        // Resolves keep the frame, so that its depths can be read.
        target.frame.keep_after_resolve(true);
        let state = ComputeCullState::new(gpu, &prepared, &target).unwrap();
        let pixels = Target::new(gpu, size.0, size.1).unwrap();
        Way {
            compute,
            prepared,
            target,
            state,
            pixels,
        }
    }

    fn draw(&self, gpu: &Gpu, iso: f32, camera: &OrbitCamera, culled: bool) -> Drawn {
        self.pixels.poison(gpu, u32::MAX).unwrap();
        let (image, triangles, culling) = if culled {
            let (image, _, stats) = self
                .compute
                .render_culled(
                    gpu,
                    &self.prepared,
                    &self.target,
                    &self.pixels,
                    &self.state,
                    iso,
                    camera,
                )
                .unwrap();
            (image, stats.triangles(), Some(stats))
        } else {
            let (image, _, stats) = self
                .compute
                .render(gpu, &self.prepared, &self.target, &self.pixels, iso, camera)
                .unwrap();
            (image, stats.triangles, None)
        };
        assert!(!image.pixels.contains(&u32::MAX), "unwritten pixels");
        let depths = self
            .target
            .frame
            .read(gpu)
            .unwrap()
            .iter()
            .map(|v| (v >> 32) as u32)
            .collect();
        Drawn {
            image,
            depths,
            triangles,
            culling,
        }
    }
}

/// The ways held to the raster pass's exact frames. The subgroup walk takes every triangle whose
/// box holds more than one pixel, so that most are walked by their subgroup at these sizes.
const CANDIDATES: [(DirectRaster, RasterVariant); 5] = [
    (DirectRaster::InExtraction, RasterVariant::Exact),
    (DirectRaster::Pass, RasterVariant::ReadBeforeAtomic),
    (DirectRaster::InExtraction, RasterVariant::ReadBeforeAtomic),
    (DirectRaster::Pass, RasterVariant::SubgroupWalk { above: 1 }),
    (
        DirectRaster::InExtraction,
        RasterVariant::SubgroupWalk { above: 1 },
    ),
];

/// Draws `path` the raster pass's way and each candidate's, culled and not, and holds every
/// candidate's frame to the raster pass's.
fn compare_ways(gpu: &Gpu, name: &str, volume: &Volume, fraction: f32, path: &[OrbitCamera]) {
    let size = (96, 80);
    let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
    let capacity = marching_cubes(volume, iso).triangle_count() as u32 + 16;
    let exact = (DirectRaster::Pass, RasterVariant::Exact);
    let candidates: Vec<_> = CANDIDATES
        .into_iter()
        .filter(|(raster, variant)| {
            let available = variant.available(gpu);
            if !available {
                eprintln!(
                    "SKIPPED: {raster:?} {}: no subgroup ballot and shuffle",
                    variant.name()
                );
            }
            available
        })
        .collect();
    for hidden_side in [HiddenSide::Skip, HiddenSide::Draw] {
        let mut ways: Vec<Way> = [exact]
            .iter()
            .chain(&candidates)
            .map(|&way| Way::new(gpu, volume, way, size, capacity))
            .collect();
        for way in &mut ways {
            way.prepared.hidden_side = hidden_side;
        }
        for culled in [false, true] {
            for (frame, camera) in path.iter().enumerate() {
                let expected = ways[0].draw(gpu, iso, camera, culled);
                let drawn = expected.depths.iter().filter(|&&d| d != u32::MAX).count();
                for (way, candidate) in ways[1..].iter().zip(&candidates) {
                    let what = format!(
                        "{name} {candidate:?} hidden side {} culled {culled} frame {frame}",
                        hidden_side.name()
                    );
                    assert!(drawn > 100, "{what}: {drawn} pixels drawn");
                    let got = way.draw(gpu, iso, camera, culled);
                    assert_eq!(got.triangles, expected.triangles, "{what}");
                    assert_eq!(got.culling, expected.culling, "{what}");
                    let wrong = got
                        .depths
                        .iter()
                        .zip(&expected.depths)
                        .filter(|(a, b)| a != b)
                        .count();
                    assert_eq!(wrong, 0, "{what}: {wrong} of {drawn} pixels' depths differ");
                    // Colours may differ only where two triangles tie in depth.
                    let diff = got.image.compare(&expected.image, 2);
                    assert!(
                        diff.fraction_within >= 0.999,
                        "{what}: {} pixels differ",
                        diff.pixels_outside
                    );
                }
            }
        }
    }
}

fn cam(azimuth_deg: f32, elevation_deg: f32, distance: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg,
        elevation_deg,
        distance,
        ..OrbitCamera::default()
    }
}

#[test]
fn extraction_that_draws_its_triangles_draws_the_raster_passes_frames() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    // A closed surface seen from outside, turning; then from inside the grid, where the near
    // plane cuts triangles (the clipping path) and both sides draw.
    let head = generate(ProceduralKind::HeadPhantom, 56, ScalarType::U8).unwrap();
    let outside = [
        cam(30.0, 20.0, 1.8),
        cam(30.0, 20.0, 1.8),
        cam(100.0, -30.0, 1.2),
    ];
    compare_ways(&gpu, "head", &head, 0.3, &outside);
    let inside = [cam(20.0, 10.0, 0.25), cam(60.0, 10.0, 0.1)];
    compare_ways(&gpu, "head inside", &head, 0.3, &inside);
    // A surface that meets the grid's boundary, and one in many pieces.
    let lobb = generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U16).unwrap();
    compare_ways(&gpu, "marschner-lobb", &lobb, 0.5, &outside[..2]);
    let blobs = generate(ProceduralKind::Turbulence, 48, ScalarType::U8).unwrap();
    compare_ways(&gpu, "turbulence", &blobs, 0.5, &outside[..2]);
    assert_clean(&gpu);
}

/// The ablations leave the fragments out: nothing is drawn, yet every tile a triangle reaches
/// is marked as the exact rasterizer marks it; without drawing, no tile is.
#[test]
fn raster_ablations_draw_nothing_and_mark_the_tiles() {
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let head = generate(ProceduralKind::HeadPhantom, 40, ScalarType::U8).unwrap();
    let iso = head.iso_to_texel(IsoValue::Normalized(0.3));
    let capacity = marching_cubes(&head, iso).triangle_count() as u32 + 16;
    let camera = cam(30.0, 20.0, 1.8);
    let tiles =
        |way: &Way| -> Vec<u32> { gpu.read_buffer_as(&way.target.frame.tile_frames).unwrap() };
    let exact = Way::new(
        &gpu,
        &head,
        (DirectRaster::Pass, RasterVariant::Exact),
        (96, 80),
        capacity,
    );
    exact.draw(&gpu, iso, &camera, false);
    let marked = tiles(&exact);
    assert!(marked.iter().filter(|&&t| t != 0).count() > 10);
    for raster in [DirectRaster::Pass, DirectRaster::InExtraction] {
        for variant in [
            RasterVariant::NoAtomics,
            RasterVariant::SetupOnly,
            RasterVariant::NoDraw,
        ] {
            assert!(!variant.is_exact());
            let way = Way::new(&gpu, &head, (raster, variant), (96, 80), capacity);
            let drawn = way.draw(&gpu, iso, &camera, false);
            assert!(
                drawn.depths.iter().all(|&d| d == u32::MAX),
                "{raster:?} {variant:?}"
            );
            assert!(drawn.triangles > 0);
            if variant == RasterVariant::NoDraw {
                // Not even a tile is marked: no triangle was looked at.
                assert!(tiles(&way).iter().all(|&t| t == 0), "{raster:?}");
            } else {
                assert_eq!(tiles(&way), marked, "{raster:?} {variant:?}");
            }
        }
    }
    assert_clean(&gpu);
}

/// Through the front door, `RendererOptions::direct_raster` draws the same images, with
/// culling off, on and chosen per frame, over a few frames of a turning camera.
#[test]
fn the_front_doors_raster_choice_draws_the_same_images() {
    use tessera::renderer::{self, Culling, RendererOptions, Technique};
    use tessera_data::scene::{Appearance, Dataset};
    let Some(gpu) = TestGpu::with(&[Need::BufferInt64Atomics]) else {
        return;
    };
    let data = Dataset::Volume(generate(ProceduralKind::HeadPhantom, 48, ScalarType::U8).unwrap());
    let look = Appearance {
        iso: IsoValue::Normalized(0.3),
        ..Appearance::default()
    };
    for culling in [Culling::Off, Culling::On, Culling::Auto] {
        let mut images = Vec::new();
        for direct_raster in [DirectRaster::Pass, DirectRaster::InExtraction] {
            let options = RendererOptions {
                path: tessera::path::PathChoice::Compute,
                culling,
                direct_raster,
                ..RendererOptions::default()
            };
            let mut r = renderer::create(&gpu, Technique::Direct, &options).unwrap();
            r.set_appearance(&gpu, &look).unwrap();
            r.set_data(&gpu, &data).unwrap();
            let mut frame = renderer::Frame::new(&gpu, (80, 64)).unwrap();
            let mut frames = Vec::new();
            for azimuth in [30.0, 30.0, 80.0] {
                let view = r.view(&cam(azimuth, 20.0, 1.8), (80, 64)).unwrap();
                frame.target.poison(&gpu, u32::MAX).unwrap();
                frame.render(&gpu, r.as_mut(), &view).unwrap();
                frames.push(frame.target.read(&gpu).unwrap());
            }
            images.push(frames);
        }
        for (k, (pass, fused)) in images[0].iter().zip(&images[1]).enumerate() {
            assert!(!fused.pixels.contains(&u32::MAX), "{culling:?} frame {k}");
            let diff = fused.compare(pass, 2);
            assert!(
                diff.fraction_within >= 0.999,
                "{culling:?} frame {k}: {} pixels differ",
                diff.pixels_outside
            );
        }
    }
    assert_clean(&gpu);
}
