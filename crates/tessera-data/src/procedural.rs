//! Deterministic synthetic volumes for tests, demos and benchmarks, so that every technique
//! can run without downloading data.
//!
//! Each field is a function `f(p)` in `[0, 1]` over `p` in `[-1, 1]^3`, sampled on a grid
//! whose first and last samples lie on the cube's faces, and quantized as `round(f * 255)`,
//! `round(f * 65535)` or stored as is. Texel space is raw units (see [`crate::volume`]), so
//! every kind spans `[0, 255]` as uint8, `[0, 65535]` as uint16 and `[0, 1]` as float32.

use std::f32::consts::PI;
use std::str::FromStr;

use glam::Vec3;
use rayon::prelude::*;

use crate::error::{DataError, Result};
use crate::volume::{Samples, ScalarType, Volume};

/// Largest edge length accepted by [`generate`] (8 GiB of `uint8` samples).
pub const MAX_SIZE: u32 = 2048;

/// The synthetic fields on offer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProceduralKind {
    /// Radial distance field: `1 - |p| / sqrt(3)`; isovalues 0.5..0.8 give spheres.
    Sphere,
    /// The Marschner–Lobb test signal (f_M = 6, alpha = 0.25), a standard reconstruction
    /// filter benchmark with fine radial ripples.
    MarschnerLobb,
    /// A CT-head-like phantom: skin ~0.25, skull ~0.9, folded brain ~0.45, dark ventricles.
    HeadPhantom,
    /// Smooth fractal gradient noise centred on 0.5.
    Turbulence,
}

impl ProceduralKind {
    pub fn name(self) -> &'static str {
        match self {
            ProceduralKind::Sphere => "sphere",
            ProceduralKind::MarschnerLobb => "marschner-lobb",
            ProceduralKind::HeadPhantom => "head",
            ProceduralKind::Turbulence => "turbulence",
        }
    }

    pub fn all() -> &'static [ProceduralKind] {
        &[
            ProceduralKind::Sphere,
            ProceduralKind::MarschnerLobb,
            ProceduralKind::HeadPhantom,
            ProceduralKind::Turbulence,
        ]
    }

    fn field(self) -> fn(Vec3) -> f32 {
        match self {
            ProceduralKind::Sphere => sphere,
            ProceduralKind::MarschnerLobb => marschner_lobb,
            ProceduralKind::HeadPhantom => head_phantom,
            ProceduralKind::Turbulence => turbulence,
        }
    }
}

impl FromStr for ProceduralKind {
    type Err = DataError;

    fn from_str(s: &str) -> Result<Self> {
        let wanted = s.trim().to_ascii_lowercase().replace('_', "-");
        Self::all()
            .iter()
            .copied()
            .find(|k| k.name() == wanted)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::all().iter().map(|k| k.name()).collect();
                DataError::Invalid(format!(
                    "unknown procedural volume '{s}' (valid: {})",
                    names.join(", ")
                ))
            })
    }
}

/// Parses `NAME:SIZE` or `NAME:SIZE:TYPE` (the part after `procedural:`); TYPE defaults to
/// uint8.
pub fn parse_spec(spec: &str) -> Result<(ProceduralKind, [u32; 3], ScalarType)> {
    let parts: Vec<&str> = spec.split(':').collect();
    let usage = || {
        DataError::Invalid(format!(
            "bad procedural spec '{spec}': expected NAME:SIZE or NAME:SIZE:TYPE with SIZE one \
             number or XxYxZ, e.g. head:256, sphere:128:uint16 or head:1024x1024x1080:uint16"
        ))
    };
    let (name, size, scalar) = match parts.as_slice() {
        [name, size] => (*name, *size, None),
        [name, size, scalar] => (*name, *size, Some(*scalar)),
        _ => return Err(usage()),
    };
    let kind = name.parse()?;
    let numbers: Vec<&str> = size.trim().split('x').collect();
    let size = match numbers.as_slice() {
        [n] => [n.parse().map_err(|_| usage())?; 3],
        [x, y, z] => [
            x.parse().map_err(|_| usage())?,
            y.parse().map_err(|_| usage())?,
            z.parse().map_err(|_| usage())?,
        ],
        _ => return Err(usage()),
    };
    let scalar = match scalar {
        None => ScalarType::U8,
        Some(s) => ScalarType::from_name(s).ok_or_else(|| {
            DataError::Invalid(format!(
                "bad procedural spec '{spec}': unknown type '{s}' (valid: uint8, uint16, float32)"
            ))
        })?,
    };
    Ok((kind, size, scalar))
}

/// Samples `kind` on a `size`^3 grid; see [`generate_grid`].
pub fn generate(kind: ProceduralKind, size: u32, scalar: ScalarType) -> Result<Volume> {
    generate_grid(kind, [size; 3], scalar)
}

/// Samples `kind` on a grid of `dims` samples spanning its [-1, 1]^3 domain on every axis (so
/// a grid longer on one axis stretches the object along it, as scanners with anisotropic
/// extents do), one z-slice per parallel task. The volume is named in the Open SciVis style,
/// e.g. `head_1024x1024x1080_uint16`, and has unit spacing.
pub fn generate_grid(kind: ProceduralKind, dims: [u32; 3], scalar: ScalarType) -> Result<Volume> {
    let what = format!("procedural {}", kind.name());
    if dims.iter().any(|&n| n < 2) {
        return Err(DataError::InvalidDims {
            what,
            dims: dims.map(u64::from),
        });
    }
    if let Some(&n) = dims.iter().find(|&&n| n > MAX_SIZE) {
        return Err(DataError::Invalid(format!(
            "{what}: size {n} exceeds the maximum of {MAX_SIZE}"
        )));
    }
    let field = kind.field();
    let samples = match scalar {
        ScalarType::U8 => Samples::U8(sample_grid(dims, field, |f| (f * 255.0).round() as u8)),
        ScalarType::U16 => Samples::U16(sample_grid(dims, field, |f| (f * 65535.0).round() as u16)),
        ScalarType::F32 => Samples::F32(sample_grid(dims, field, |f| f)),
    };
    let [x, y, z] = dims;
    let name = format!("{}_{x}x{y}x{z}_{}", kind.name(), scalar.name());
    Volume::new(name, dims, [1.0; 3], samples)
}

fn sample_grid<T, Q>(dims: [u32; 3], field: fn(Vec3) -> f32, quantize: Q) -> Vec<T>
where
    T: Copy + Default + Send,
    Q: Fn(f32) -> T + Sync,
{
    let [nx, ny, nz] = dims.map(|n| n as usize);
    let steps = dims.map(|n| 2.0 / (n - 1) as f32);
    let coord = |i: usize, axis: usize| -1.0 + i as f32 * steps[axis];
    let mut out = vec![T::default(); nx * ny * nz];
    out.par_chunks_mut(nx * ny)
        .enumerate()
        .for_each(|(z, slice)| {
            for (y, row) in slice.chunks_mut(nx).enumerate() {
                for (x, v) in row.iter_mut().enumerate() {
                    let f = field(Vec3::new(coord(x, 0), coord(y, 1), coord(z, 2)));
                    // NaN-safe clamp: a NaN would become 0 rather than poison the volume.
                    *v = quantize(if f >= 0.0 { f.min(1.0) } else { 0.0 });
                }
            }
        });
    out
}

fn sphere(p: Vec3) -> f32 {
    1.0 - p.length() / 3f32.sqrt()
}

fn marschner_lobb(p: Vec3) -> f32 {
    const F_M: f32 = 6.0;
    const ALPHA: f32 = 0.25;
    let r = (p.x * p.x + p.y * p.y).sqrt();
    let rho_r = (2.0 * PI * F_M * (PI * r / 2.0).cos()).cos();
    (1.0 - (PI * p.z / 2.0).sin() + ALPHA * (1.0 + rho_r)) / (2.0 * (1.0 + ALPHA))
}

/// 1 inside, 0 outside an ellipsoid given as a normalized radius, with a soft edge a couple
/// of voxels wide at typical sizes so that isosurfaces are not stair-stepped.
fn inside(r: f32) -> f32 {
    const EDGE: f32 = 0.012;
    1.0 - smoothstep(1.0 - EDGE, 1.0 + EDGE, r)
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

fn head_phantom(p: Vec3) -> f32 {
    // x: left-right, y: back-front, z: down-up.
    let q = p - Vec3::new(0.0, 0.0, 0.04);
    let head = (q / Vec3::new(0.70, 0.86, 0.90)).length();
    if head > 1.05 {
        return 0.0;
    }
    const SKIN: f32 = 0.25;
    const BONE: f32 = 0.9;
    const CSF: f32 = 0.12;
    const BRAIN: f32 = 0.45;
    // Brain and skull share the head's shape, scaled; noise displaces the brain's surface
    // into gyri and sulci.
    let folds = gradient_noise(q * 9.0 + Vec3::splat(11.3), 101);
    let brain_r = head / 0.78 + 0.06 * folds;
    let tissue = BRAIN + 0.04 * gradient_noise(q * 13.0, 202);
    let vent_l = ((q - Vec3::new(-0.11, 0.02, 0.14)) / Vec3::new(0.07, 0.24, 0.10)).length();
    let vent_r = ((q - Vec3::new(0.11, 0.02, 0.14)) / Vec3::new(0.07, 0.24, 0.10)).length();

    let mut v = 0.0;
    v = lerp(v, SKIN, inside(head));
    v = lerp(v, BONE, inside(head / 0.93));
    v = lerp(v, CSF, inside(head / 0.84));
    v = lerp(v, tissue, inside(brain_r));
    v = lerp(v, CSF, inside(vent_l.min(vent_r)));
    // Mild acquisition-like noise inside the head only, so the air stays exactly 0.
    v + 0.015 * inside(head) * gradient_noise(p * 29.0, 303)
}

fn turbulence(p: Vec3) -> f32 {
    const OCTAVES: u32 = 5;
    let mut sum = 0.0;
    let mut amp = 1.0;
    let mut q = p * 2.0 + Vec3::new(0.37, 0.71, 0.13);
    for octave in 0..OCTAVES {
        sum += amp * gradient_noise(q, 17 + octave);
        amp *= 0.5;
        q = q * 2.0 + Vec3::splat(0.5);
    }
    // Scale chosen so that only rare extremes reach the clamp while most of [0, 1] is used.
    0.5 + 0.7 * sum
}

/// Integer hash of a lattice point; any good avalanche is fine, it only has to be fixed.
fn hash(x: i32, y: i32, z: i32, seed: u32) -> u32 {
    let mut h = seed.wrapping_mul(0x9E37_79B9)
        ^ (x as u32).wrapping_mul(0x8DA6_B343)
        ^ (y as u32).wrapping_mul(0xD816_3841)
        ^ (z as u32).wrapping_mul(0xCB1A_B31F);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7FEB_352D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846C_A68B);
    h ^ (h >> 16)
}

/// Dot product of a pseudo-random cube-edge direction with `d`.
fn grad_dot(h: u32, d: Vec3) -> f32 {
    match h >> 28 {
        0 | 12 => d.x + d.y,
        1 | 13 => -d.x + d.y,
        2 => d.x - d.y,
        3 => -d.x - d.y,
        4 | 14 => d.x + d.z,
        5 => -d.x + d.z,
        6 => d.x - d.z,
        7 => -d.x - d.z,
        8 => d.y + d.z,
        9 | 15 => -d.y + d.z,
        10 => d.y - d.z,
        _ => -d.y - d.z,
    }
}

/// Lattice gradient noise in about [-1, 1], C2-continuous thanks to the quintic fade.
fn gradient_noise(p: Vec3, seed: u32) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let (ix, iy, iz) = (cell.x as i32, cell.y as i32, cell.z as i32);
    let u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let corner = |dx: i32, dy: i32, dz: i32| {
        let h = hash(ix + dx, iy + dy, iz + dz, seed);
        grad_dot(h, f - Vec3::new(dx as f32, dy as f32, dz as f32))
    };
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), u.x);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), u.x);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), u.x);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), u.x);
    lerp(lerp(x00, x10, u.y), lerp(x01, x11, u.y), u.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f32_samples(v: &Volume) -> &[f32] {
        match v.samples() {
            Samples::F32(s) => s,
            other => panic!("expected f32 samples, got {:?}", other.scalar_type()),
        }
    }

    #[test]
    fn names_parse_and_specs() {
        for kind in ProceduralKind::all() {
            assert_eq!(kind.name().parse::<ProceduralKind>().ok(), Some(*kind));
        }
        assert_eq!(
            "Marschner_Lobb".parse::<ProceduralKind>().ok(),
            Some(ProceduralKind::MarschnerLobb)
        );
        let err = "teapot".parse::<ProceduralKind>().unwrap_err().to_string();
        assert!(
            err.contains("teapot") && err.contains("marschner-lobb") && err.contains("head"),
            "{err}"
        );

        let spec = parse_spec("head:64").expect("spec");
        assert_eq!(spec, (ProceduralKind::HeadPhantom, [64; 3], ScalarType::U8));
        let spec = parse_spec("sphere:32:uint16").expect("spec");
        assert_eq!(spec, (ProceduralKind::Sphere, [32; 3], ScalarType::U16));
        let spec = parse_spec("head:16x12x20:uint16").expect("spec");
        assert_eq!(
            spec,
            (ProceduralKind::HeadPhantom, [16, 12, 20], ScalarType::U16)
        );
        for bad in [
            "head",
            "head:x",
            "head:16x12",
            "head:16x12x",
            "head:16x12x20x3",
            "head:64:int8",
            "cube:64",
            "head:64:u8:extra",
        ] {
            let err = parse_spec(bad).expect_err(bad).to_string();
            assert!(err.contains(bad.split(':').next().unwrap_or(bad)), "{err}");
        }
    }

    #[test]
    fn dims_types_and_bad_sizes() {
        for kind in ProceduralKind::all() {
            for scalar in [ScalarType::U8, ScalarType::U16, ScalarType::F32] {
                let v = generate(*kind, 9, scalar).expect("generate");
                assert_eq!(v.dims(), [9, 9, 9]);
                assert_eq!(v.scalar_type(), scalar);
                assert_eq!(v.sample_count(), 729);
                let top = match scalar {
                    ScalarType::U8 => 255.0,
                    ScalarType::U16 => 65535.0,
                    ScalarType::F32 => 1.0,
                };
                let (lo, hi) = v.texel_range();
                assert!((0.0..=top).contains(&lo) && (0.0..=top).contains(&hi) && lo < hi);
            }
        }
        assert_eq!(
            generate(ProceduralKind::Sphere, 5, ScalarType::U8)
                .expect("v")
                .name(),
            "sphere_5x5x5_uint8"
        );
        let stretched = generate_grid(ProceduralKind::Sphere, [9, 5, 17], ScalarType::F32)
            .expect("a grid of three sizes");
        assert_eq!(stretched.dims(), [9, 5, 17]);
        assert_eq!(stretched.name(), "sphere_9x5x17_float32");
        // The domain spans every axis: the centre sample is the sphere's maximum and the
        // corners its minimum, whatever the axis lengths.
        let cube = generate(ProceduralKind::Sphere, 9, ScalarType::F32).expect("cube");
        assert_eq!(stretched.texel_range(), cube.texel_range());
        assert!(generate_grid(ProceduralKind::Sphere, [9, 1, 9], ScalarType::U8).is_err());
        for size in [0, 1] {
            let err = generate(ProceduralKind::Sphere, size, ScalarType::U8).expect_err("small");
            assert!(matches!(err, DataError::InvalidDims { .. }), "{err}");
        }
        assert!(generate(ProceduralKind::Sphere, MAX_SIZE + 1, ScalarType::U8).is_err());
    }

    #[test]
    fn deterministic_and_in_unit_range() {
        for kind in ProceduralKind::all() {
            let a = generate(*kind, 33, ScalarType::F32).expect("a");
            let b = generate(*kind, 33, ScalarType::F32).expect("b");
            assert_eq!(a.samples(), b.samples(), "{kind:?}");
            assert!(f32_samples(&a).iter().all(|v| (0.0..=1.0).contains(v)));
            let q = generate(*kind, 33, ScalarType::U16).expect("q");
            assert_eq!(
                q.samples(),
                generate(*kind, 33, ScalarType::U16).expect("q").samples()
            );
            // Quantization is round(f * 65535) of the same field.
            let (x, y, z) = (5, 17, 30);
            assert_eq!(q.texel(x, y, z), (a.texel(x, y, z) * 65535.0).round());
        }
    }

    #[test]
    fn marschner_lobb_matches_formula() {
        let v = generate(ProceduralKind::MarschnerLobb, 41, ScalarType::F32).expect("ml");
        for (x, y, z) in [(0, 0, 0), (20, 20, 20), (7, 33, 12), (40, 3, 25)] {
            let [px, py, pz] = [x, y, z].map(|i| -1.0 + 2.0 * i as f64 / 40.0);
            let pi = std::f64::consts::PI;
            let r = (px * px + py * py).sqrt();
            let rho_r = (2.0 * pi * 6.0 * (pi * r / 2.0).cos()).cos();
            let want = (1.0 - (pi * pz / 2.0).sin() + 0.25 * (1.0 + rho_r)) / (2.0 * 1.25);
            let got = v.texel(x, y, z) as f64;
            assert!((got - want).abs() < 1e-5, "({x},{y},{z}): {got} vs {want}");
        }
        let u8v = generate(ProceduralKind::MarschnerLobb, 41, ScalarType::U8).expect("ml");
        let want = (v.texel(7, 33, 12) * 255.0).round();
        assert_eq!(u8v.texel(7, 33, 12), want);
    }

    #[test]
    fn sphere_and_head_structure() {
        let s = generate(ProceduralKind::Sphere, 21, ScalarType::F32).expect("sphere");
        assert_eq!(s.texel(10, 10, 10), 1.0);
        assert!(s.texel(0, 0, 0).abs() < 1e-6);

        // Walking out from the centre along +x must cross brain, skull, skin and air.
        let h = generate(ProceduralKind::HeadPhantom, 129, ScalarType::F32).expect("head");
        let profile: Vec<f32> = (64..129).map(|x| h.texel(x, 64, 60)).collect();
        let seen = |lo: f32, hi: f32| profile.iter().any(|v| (lo..=hi).contains(v));
        assert!(seen(0.38, 0.52), "brain {profile:?}");
        assert!(seen(0.85, 1.0), "skull {profile:?}");
        assert!(seen(0.2, 0.3), "skin {profile:?}");
        assert_eq!(profile.last().copied(), Some(0.0));
        assert_eq!(h.texel(0, 0, 0), 0.0);
    }

    #[test]
    fn turbulence_is_centred_and_varied() {
        let t = generate(ProceduralKind::Turbulence, 48, ScalarType::F32).expect("turb");
        let s = f32_samples(&t);
        let mean = s.iter().sum::<f32>() / s.len() as f32;
        let below = s.iter().filter(|&&v| v < 0.5).count() as f32 / s.len() as f32;
        assert!((mean - 0.5).abs() < 0.1, "mean {mean}");
        assert!((0.3..0.7).contains(&below), "below {below}");
        let (lo, hi) = t.texel_range();
        assert!(lo < 0.2 && hi > 0.8, "range {lo}..{hi}");
        // Smooth: neighbouring samples differ far less than the full range.
        let max_step = s
            .chunks(48)
            .flat_map(|row| row.windows(2).map(|w| (w[1] - w[0]).abs()))
            .fold(0.0, f32::max);
        assert!(max_step < 0.5, "step {max_step}");
    }
}
