//! The GPU ray marcher and its min-max octree against the CPU references, on lavapipe or a GPU.

mod common;

use common::{assert_clean, assert_images_match, gpu};
use tessera::gpu_volume::GpuVolume;
use tessera::iso::minmax::{samples_buffer_size, LevelZeroPass, MinMaxBuilder, MinMaxOctreeGpu};
use tessera::iso::raymarch::Raymarch;
use tessera::shaders;
use tessera::target::Target;
use tessera_data::minmax::MinMaxOctree;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{raycast, IsoValue, OrbitCamera, Samples, ScalarType, Volume};
use tessera_gpu::vk;

const POISON: u32 = u32::MAX;

fn volumes() -> Vec<Volume> {
    vec![
        generate(ProceduralKind::HeadPhantom, 40, ScalarType::U8).unwrap(),
        generate(ProceduralKind::MarschnerLobb, 33, ScalarType::U16).unwrap(),
        generate(ProceduralKind::Turbulence, 29, ScalarType::F32).unwrap(),
    ]
}

#[test]
fn gpu_octree_equals_cpu_octree_exactly() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    // Odd sizes on purpose: partial blocks at the upper faces are where indexing goes wrong.
    let mut vols = volumes();
    let n = 23 * 18 * 11;
    let ramp: Vec<f32> = (0..n).map(|i| ((i * 37) % 101) as f32 - 50.5).collect();
    vols.push(Volume::new("ramp", [23, 18, 11], [1.0; 3], Samples::F32(ramp)).unwrap());
    for volume in &vols {
        let rm = Raymarch::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = rm.prepare(&gpu, volume).unwrap();
        let cpu = MinMaxOctree::build(volume);
        let gpu_nodes = prepared.octree.read(&gpu).unwrap();
        assert_eq!(gpu_nodes.len(), cpu.flattened().len(), "{}", volume.name());
        assert_eq!(gpu_nodes, cpu.flattened(), "octree of {}", volume.name());
        assert_eq!(prepared.octree.level_dims.len(), cpu.levels.len());
    }
    assert_clean(&gpu);
}

#[test]
fn every_level_zero_pass_gives_the_cpu_octree() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let mut passes = vec![
        LevelZeroPass::PerBlock { subgroups: false },
        LevelZeroPass::Grouped,
    ];
    if gpu.caps().subgroup_arithmetic {
        passes.push(LevelZeroPass::PerBlock { subgroups: true });
    }
    // Odd block counts (partial groups of 2×2×2 blocks), one block (no level 1), and a
    // volume whose last block row is a single plane of samples.
    // Then volumes of 6 and 8 levels (two and three level passes) with a hash-like field, so
    // that every node's range differs.
    let n = 23 * 18 * 11;
    let ramp: Vec<f32> = (0..n).map(|i| ((i * 37) % 101) as f32 - 50.5).collect();
    let hashed = |i: usize| (i.wrapping_mul(2_654_435_761) >> 7) % 997;
    let long: Vec<u16> = (0..521 * 5 * 9).map(|i| hashed(i) as u16).collect();
    let wide: Vec<u8> = (0..137 * 67 * 35)
        .map(|i| (hashed(i) % 251) as u8)
        .collect();
    // Rows of whole words (the buffer pass's load-ahead walk), with a partial last block.
    let wide_words: Vec<u8> = (0..132 * 19 * 13)
        .map(|i| (hashed(i + 7) % 256) as u8)
        .collect();
    let long_words: Vec<u16> = (0..522 * 6 * 9).map(|i| hashed(i + 3) as u16).collect();
    let volumes = [
        generate(ProceduralKind::Turbulence, 37, ScalarType::U16).unwrap(),
        Volume::new("ramp", [23, 18, 11], [1.0; 3], Samples::F32(ramp)).unwrap(),
        generate(ProceduralKind::MarschnerLobb, 5, ScalarType::U8).unwrap(),
        generate(ProceduralKind::Sphere, 17, ScalarType::F32).unwrap(),
        Volume::new("long", [521, 5, 9], [1.0; 3], Samples::U16(long)).unwrap(),
        Volume::new("wide", [137, 67, 35], [1.0; 3], Samples::U8(wide)).unwrap(),
        Volume::new(
            "wide words",
            [132, 19, 13],
            [1.0; 3],
            Samples::U8(wide_words),
        )
        .unwrap(),
        Volume::new(
            "long words",
            [522, 6, 9],
            [1.0; 3],
            Samples::U16(long_words),
        )
        .unwrap(),
    ];
    for volume in &volumes {
        let cpu = MinMaxOctree::build(volume).flattened();
        let gpu_volume = GpuVolume::upload(&gpu, volume).unwrap();
        for &pass in &passes {
            let builder =
                MinMaxBuilder::with_pass(&gpu, &compiler, volume.scalar_type(), pass).unwrap();
            let octree = MinMaxOctreeGpu::allocate(&gpu, volume.dims()).unwrap();
            gpu.submit("poison", |rec| rec.fill_buffer(&octree.nodes, POISON))
                .unwrap();
            gpu.submit("build", |rec| builder.record(rec, &gpu_volume, &octree))
                .unwrap();
            assert_eq!(
                octree.read(&gpu).unwrap(),
                cpu,
                "{pass:?}, {}",
                volume.name()
            );
        }
        // Level 0 from a buffer of the samples: odd row lengths start rows mid-word; rows of
        // whole words take the walk that loads ahead.
        let builder = MinMaxBuilder::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let mut words = volume.bytes().to_vec();
        words.resize(
            samples_buffer_size(volume.scalar_type(), volume.dims()) as usize,
            0xAB,
        );
        let samples = gpu
            .upload_buffer("samples", &words, vk::BufferUsageFlags::STORAGE_BUFFER)
            .unwrap();
        let octree = MinMaxOctreeGpu::allocate(&gpu, volume.dims()).unwrap();
        // Twice, the nodes poisoned before each: a build depends on nothing the last left.
        for build in 0..2 {
            gpu.submit("poison", |rec| rec.fill_buffer(&octree.nodes, POISON))
                .unwrap();
            let mut recorded = Ok(());
            gpu.submit("build from samples", |rec| {
                recorded = builder.record_from_samples(rec, &samples, volume.dims(), &octree)
            })
            .unwrap();
            recorded.unwrap();
            assert_eq!(
                octree.read(&gpu).unwrap(),
                cpu,
                "from samples, build {build}, {}",
                volume.name()
            );
        }
        // A buffer short of the volume is refused.
        let short = gpu
            .upload_buffer(
                "short",
                &words[..words.len() - 4],
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )
            .unwrap();
        let mut refused = Ok(());
        gpu.submit("refused", |rec| {
            refused = builder.record_from_samples(rec, &short, volume.dims(), &octree)
        })
        .unwrap();
        assert!(refused
            .unwrap_err()
            .to_string()
            .contains("samples buffer holds"));
    }
    assert_clean(&gpu);
}

#[test]
fn raymarched_images_match_cpu_reference() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let (w, h) = (128, 112);
    let camera = OrbitCamera {
        azimuth_deg: 35.0,
        elevation_deg: 25.0,
        distance: 1.9,
        eye_shift: 0.0,
        eye_rise: 0.0,
        up: Default::default(),
        fov_y_deg: 40.0,
    };
    let target = Target::new(&gpu, w, h).unwrap();
    for volume in volumes() {
        let rm = Raymarch::new(&gpu, &compiler, volume.scalar_type()).unwrap();
        let prepared = rm.prepare(&gpu, &volume).unwrap();
        for fraction in [0.3f32, 0.6] {
            let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
            target.poison(&gpu, POISON).unwrap();
            let (image, _ms) = rm.render(&gpu, &prepared, &target, iso, &camera).unwrap();
            assert!(!image.pixels.contains(&POISON), "unwritten pixels");
            let reference = raycast::render(&volume, iso, &camera, w, h);
            let name = format!("raymarch-{}-{fraction}", volume.name());
            assert_images_match(&name, &image, &reference, 2, 0.99);
            // The surface must be in view: a test that only saw background would prove nothing.
            let background = tessera_data::shading::pack_rgba8(tessera_data::shading::BACKGROUND);
            let hits = image.pixels.iter().filter(|&&p| p != background).count();
            assert!(
                hits > (w * h / 20) as usize,
                "{name}: only {hits} surface pixels"
            );
        }
    }
    assert_clean(&gpu);
}

#[test]
fn isovalue_outside_range_renders_background_only() {
    let gpu = gpu();
    let compiler = shaders::compiler();
    let volume = generate(ProceduralKind::Sphere, 24, ScalarType::U8).unwrap();
    let rm = Raymarch::new(&gpu, &compiler, ScalarType::U8).unwrap();
    let prepared = rm.prepare(&gpu, &volume).unwrap();
    let target = Target::new(&gpu, 32, 32).unwrap();
    target.poison(&gpu, POISON).unwrap();
    let (image, _) = rm
        .render(&gpu, &prepared, &target, 300.0, &OrbitCamera::default())
        .unwrap();
    let background = tessera_data::shading::pack_rgba8(tessera_data::shading::BACKGROUND);
    assert!(image.pixels.iter().all(|&p| p == background));
    assert_clean(&gpu);
}
