//! Small synthetic volumes for tests: a field sampled on the grid, and reproducible noise.

use glam::Vec3;

use crate::volume::{Samples, Volume};

/// `f` sampled at every grid point `(x, y, z)` as float32, unit spacing.
pub fn field(dims: [u32; 3], f: impl Fn(Vec3) -> f32) -> Volume {
    let mut v = Vec::new();
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                v.push(f(Vec3::new(x as f32, y as f32, z as f32)));
            }
        }
    }
    Volume::new("test", dims, [1.0; 3], Samples::F32(v)).unwrap()
}

/// Uniform values in [0, 1), one per sample of `dims`, the same for the same `seed`.
pub fn noise(dims: [u32; 3], seed: u64) -> Vec<f32> {
    let mut s = seed;
    let n = dims.iter().product::<u32>();
    (0..n)
        .map(|_| {
            // splitmix64: a tiny, dependency-free, reproducible generator.
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        })
        .collect()
}
