//! Volumes and isovalues the extraction tests share (the meshlet and PMB paths are held to
//! the same surfaces).

use super::field;
use glam::Vec3;
use tessera::iso::minmax::MinMaxBuilder;
use tessera::iso::PreparedVolume;
use tessera::shaders;
use tessera_data::procedural::{generate, ProceduralKind};
use tessera_data::{ScalarType, Volume};
use tessera_gpu::Gpu;

/// Reproducible values in [0, 1) from a multiplicative hash of the sample position.
pub fn noise(name: &str, dims: [u32; 3]) -> Volume {
    field(name, dims, |p| {
        let [x, y, z] = p.to_array().map(|c| c as u32);
        let h =
            (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663) ^ z.wrapping_mul(83_492_791))
                .wrapping_mul(2_654_435_761);
        (h >> 8) as f32 / (1u32 << 24) as f32
    })
}

/// `(volume, iso)` pairs of several characters; no isovalue equals a sample. Only the sphere
/// has dims that are whole blocks plus one sample (33 = 4·8 + 1 along x and y, 8·4 + 1 along
/// z); the others end in partial blocks along some axes.
pub fn extraction_volumes() -> Vec<(Volume, f32)> {
    let sphere = generate(ProceduralKind::Sphere, 33, ScalarType::F32).unwrap();
    let spheres = field("three spheres", [30, 26, 19], |p| {
        let centres = [
            Vec3::new(8.0, 9.0, 7.0),
            Vec3::new(20.0, 15.0, 10.0),
            Vec3::new(13.0, 18.0, 12.0),
        ];
        centres
            .iter()
            .map(|c| 6.5 - p.distance(*c))
            .fold(f32::MIN, f32::max)
    });
    let gyroid = field("gyroid", [23, 17, 14], |p| {
        let q = p * 0.55;
        q.x.sin() * q.y.cos() + q.y.sin() * q.z.cos() + q.z.sin() * q.x.cos()
    });
    let turbulence = generate(ProceduralKind::Turbulence, 26, ScalarType::U8).unwrap();
    vec![
        (sphere, 0.6123),
        (spheres, 0.0513),
        (gyroid, 0.1037),
        (noise("noise", [13, 21, 7]), 0.5),
        (turbulence, 127.5),
    ]
}

/// `volume` uploaded with its min-max octree.
pub fn prepare(gpu: &Gpu, volume: &Volume) -> PreparedVolume {
    let builder = MinMaxBuilder::new(gpu, &shaders::compiler(), volume.scalar_type()).unwrap();
    PreparedVolume::new(gpu, &builder, volume).unwrap()
}

/// Every output buffer of a PMB extraction filled with `u32::MAX` (NaN bits for floats, index
/// 0xffff), so anything the extraction leaves unwritten shows.
pub fn poison_pmb(gpu: &Gpu, out: &tessera::iso::pmb::GpuPmb) {
    gpu.submit("poison PMB outputs", |rec| {
        for buffer in [&out.descriptors, &out.positions, &out.normals, &out.indices] {
            rec.fill_buffer(buffer, u32::MAX);
        }
    })
    .unwrap();
}
