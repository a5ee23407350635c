//! The signed-distance-field scene of paper A §3.2 (after Neyret's asteroid field): every
//! asteroid is a noise-displaced sphere inside its own bounding tetrahedron, and a pixel
//! sphere-traces an asteroid only along the interval its ray spends in that tet, so the work of
//! one ray is spread over the tets it crosses and the nearest hit wins by depth.
//!
//! This module holds the scene generator and the CPU reference: the distance function, the
//! tracing loop and the shading, with the constants the GPU shaders receive as defines
//! (`tet/interval/sdf.glsl` mirrors every function here in `f32`). The noise is value noise on
//! an integer lattice hashed with PCG3D (Jarzynski and Olano 2020), which integer arithmetic
//! makes identical on both sides.

use glam::DVec3;

use super::optical::{accumulate_with, world_tet, MeshFrame, RayStretch};
use super::TetMesh;
use crate::camera::OrbitCamera;
use crate::image::RgbaImage;
use crate::shading::pack_rgba8;

/// Surface displacement as a fraction of the asteroid's radius, per unit of noise.
pub const AMPLITUDE: f64 = 0.2;
/// Noise lattice cells per asteroid radius at the first octave.
pub const FREQUENCY: f64 = 1.5;
pub const OCTAVES: u32 = 3;
/// The asteroid's base radius as a fraction of its tet's inradius: with the noise's bound
/// (|fbm| < 0.875) the surface stays inside the tet.
pub const RADIUS_IN_TET: f64 = 0.8;
/// Sphere-tracing steps per interval, and the fraction of the distance each step advances
/// (the displaced distance is not exact, so steps are shortened).
pub const STEPS: u32 = 64;
pub const STEP_SCALE: f64 = 0.5;
/// A hit is a distance below this fraction of the asteroid's radius.
pub const EPSILON: f64 = 1e-3;
/// Towards the light (world space, normalized where used).
pub const LIGHT: [f64; 3] = [0.5, 0.8, 0.3];
pub const AMBIENT: f64 = 0.25;
pub const DARK_ROCK: [f64; 3] = [0.30, 0.26, 0.23];
pub const LIGHT_ROCK: [f64; 3] = [0.62, 0.57, 0.50];

/// A field of `count` asteroids in the unit cube, each bounded by a regular tetrahedron of
/// random size and placement (deterministic in `seed`); the tets do not share vertices.
pub fn asteroid_field(count: u32, seed: u64) -> TetMesh {
    let mut rng = SplitMix(seed);
    // Regular tet with inradius 1: vertices at distance 3 from the centre.
    let corners = [
        DVec3::new(1.0, 1.0, 1.0),
        DVec3::new(1.0, -1.0, -1.0),
        DVec3::new(-1.0, 1.0, -1.0),
        DVec3::new(-1.0, -1.0, 1.0),
    ]
    .map(|c| c * 3.0_f64.sqrt());
    // Sizes shrink with the count so that the field keeps roughly the same density.
    let scale = 0.35 / f64::from(count.max(1)).cbrt();
    let mut vertices = Vec::with_capacity(count as usize * 4);
    let mut tets = Vec::with_capacity(count as usize);
    for i in 0..count {
        let centre = DVec3::new(rng.unit(), rng.unit(), rng.unit());
        let inradius = scale * (0.5 + rng.unit());
        let angle = rng.unit() * std::f64::consts::TAU;
        let (s, c) = angle.sin_cos();
        for v in corners {
            // A turn about z, so the tets do not all line up.
            let v = DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
            vertices.push((centre + v * inradius).as_vec3().to_array());
        }
        tets.push([4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3]);
    }
    let mut mesh = TetMesh::new(vertices, tets);
    mesh.regions = Some((0..count).collect());
    mesh
}

/// Per tet, in world space ([`MeshFrame::of`]): its centroid and the radius of its asteroid
/// ([`RADIUS_IN_TET`] × its inradius).
pub fn asteroid_spheres(mesh: &TetMesh) -> Vec<[f32; 4]> {
    let frame = MeshFrame::of(mesh);
    (0..mesh.tets.len())
        .map(|t| {
            let c = world_tet(mesh, &frame, t);
            let centre = (c[0] + c[1] + c[2] + c[3]) * 0.25;
            let volume = (c[1] - c[0]).dot((c[2] - c[0]).cross(c[3] - c[0])).abs() / 6.0;
            let area: f64 = [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)]
                .iter()
                .map(|&(a, b, d)| (c[b] - c[a]).cross(c[d] - c[a]).length() * 0.5)
                .sum();
            let inradius = if area > 0.0 { 3.0 * volume / area } else { 0.0 };
            let r = RADIUS_IN_TET * inradius;
            [centre.x as f32, centre.y as f32, centre.z as f32, r as f32]
        })
        .collect()
}

/// PCG3D: three 32-bit words scrambled together (mix, xor-shift, mix).
pub fn pcg3d(v: [u32; 3]) -> [u32; 3] {
    let mix = |[x, y, z]: [u32; 3]| {
        let x = x.wrapping_add(y.wrapping_mul(z));
        let y = y.wrapping_add(z.wrapping_mul(x));
        let z = z.wrapping_add(x.wrapping_mul(y));
        [x, y, z]
    };
    let v = mix(v.map(|w| w.wrapping_mul(1_664_525).wrapping_add(1_013_904_223)));
    mix(v.map(|w| w ^ (w >> 16)))
}

/// Value noise in [0, 1): hashed lattice values, blended with the quintic fade.
pub fn value_noise(p: DVec3, seed: u32) -> f64 {
    let cell = p.floor();
    let f = p - cell;
    let fade = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let base = [cell.x as i32, cell.y as i32, cell.z as i32];
    let lattice = |dx: i32, dy: i32, dz: i32| {
        let h = pcg3d([
            (base[0] + dx) as u32,
            (base[1] + dy) as u32,
            ((base[2] + dz) as u32) ^ seed.wrapping_mul(0x9E37_79B9),
        ]);
        f64::from(h[0] >> 8) / f64::from(1u32 << 24)
    };
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let x00 = lerp(lattice(0, 0, 0), lattice(1, 0, 0), fade.x);
    let x10 = lerp(lattice(0, 1, 0), lattice(1, 1, 0), fade.x);
    let x01 = lerp(lattice(0, 0, 1), lattice(1, 0, 1), fade.x);
    let x11 = lerp(lattice(0, 1, 1), lattice(1, 1, 1), fade.x);
    lerp(lerp(x00, x10, fade.y), lerp(x01, x11, fade.y), fade.z)
}

/// Fractal sum of [`OCTAVES`] octaves of centred value noise, in (-0.875, 0.875).
pub fn fbm(p: DVec3, seed: u32) -> f64 {
    let mut sum = 0.0;
    let mut amplitude = 1.0;
    let mut q = p;
    for _ in 0..OCTAVES {
        sum += amplitude * (value_noise(q, seed) - 0.5);
        amplitude *= 0.5;
        q *= 2.0;
    }
    sum
}

/// Signed distance (approximately: the displacement makes it a bound only up to its slope) to
/// asteroid `seed` of centre `sphere.xyz` and radius `sphere.w`.
pub fn asteroid_distance(p: DVec3, sphere: [f32; 4], seed: u32) -> f64 {
    let centre = DVec3::new(sphere[0].into(), sphere[1].into(), sphere[2].into());
    let radius = f64::from(sphere[3]);
    let q = p - centre;
    let bumps = fbm(q / radius * FREQUENCY, seed);
    q.length() - radius * (1.0 + AMPLITUDE * bumps)
}

/// Sphere tracing from `t0` to `t1` along the unit ray; the distance of the hit, if any.
pub fn trace(eye: DVec3, dir: DVec3, t0: f64, t1: f64, sphere: [f32; 4], seed: u32) -> Option<f64> {
    let epsilon = EPSILON * f64::from(sphere[3]);
    let mut t = t0;
    for _ in 0..STEPS {
        let d = asteroid_distance(eye + dir * t, sphere, seed);
        if d < epsilon {
            return Some(t);
        }
        t += d * STEP_SCALE;
        if t > t1 {
            return None;
        }
    }
    None
}

/// Colour of the asteroid's surface at `p`: Lambert + ambient on an albedo between two rock
/// tones picked by the noise; the normal from central differences.
pub fn shade(p: DVec3, sphere: [f32; 4], seed: u32) -> [f64; 3] {
    let h = EPSILON * f64::from(sphere[3]);
    let d = |o: DVec3| asteroid_distance(p + o, sphere, seed);
    let normal = DVec3::new(
        d(DVec3::X * h) - d(-DVec3::X * h),
        d(DVec3::Y * h) - d(-DVec3::Y * h),
        d(DVec3::Z * h) - d(-DVec3::Z * h),
    )
    .normalize_or_zero();
    let light = DVec3::from(LIGHT).normalize();
    let lit = AMBIENT + (1.0 - AMBIENT) * normal.dot(light).max(0.0);
    let centre = DVec3::new(sphere[0].into(), sphere[1].into(), sphere[2].into());
    let tone = value_noise((p - centre) / f64::from(sphere[3]) * 4.0, seed ^ 1);
    std::array::from_fn(|c| lit * (DARK_ROCK[c] + (LIGHT_ROCK[c] - DARK_ROCK[c]) * tone))
}

/// The nearest hit along one pixel's ray so far.
#[derive(Clone, Copy, Debug, Default)]
struct Nearest {
    hit: Option<(f64, [f64; 3])>,
}

/// The CPU reference image of an asteroid field (per-tet spheres from [`asteroid_spheres`],
/// asteroid `t` seeded with `t`): the nearest hit's colour per pixel, `background` elsewhere;
/// and which pixels hit.
pub fn render_reference(
    mesh: &TetMesh,
    spheres: &[[f32; 4]],
    camera: &OrbitCamera,
    (width, height): (u32, u32),
    background: [f32; 3],
) -> (RgbaImage, Vec<bool>) {
    let nearest = accumulate_with(
        mesh,
        camera,
        width,
        height,
        |t, ray: RayStretch, best: &mut Nearest| {
            let seed = t as u32;
            if let Some(hit) = trace(ray.eye, ray.dir, ray.enter, ray.exit, spheres[t], seed) {
                if best.hit.is_none_or(|(d, _)| hit < d) {
                    let colour = shade(ray.eye + ray.dir * hit, spheres[t], seed);
                    best.hit = Some((hit, colour));
                }
            }
        },
    );
    let pixels = nearest
        .iter()
        .map(|n| match n.hit {
            Some((_, c)) => pack_rgba8([c[0] as f32, c[1] as f32, c[2] as f32, 1.0]),
            None => pack_rgba8([background[0], background[1], background[2], 1.0]),
        })
        .collect();
    let hits = nearest.iter().map(|n| n.hit.is_some()).collect();
    (
        RgbaImage {
            width,
            height,
            pixels,
        },
        hits,
    )
}

/// A small deterministic generator for scene layout (SplitMix64).
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
#[path = "asteroids_tests.rs"]
mod tests;
