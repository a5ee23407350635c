//! CPU reference isosurface ray caster: the ground truth for the GPU `raymarch` technique.
//!
//! Rays are sampled at fixed steps of half a cell from where they enter the volume, so the GPU
//! may skip empty space and still visit exactly the samples this plain march visits. The first
//! step whose end lies on the other side of the isovalue is refined by 3 bisections and a final
//! linear interpolation; the normal is the central-difference gradient (one grid unit), and the
//! surface is Gooch shaded.

use crate::camera::{GridCamera, GridFrame, OrbitCamera};
use crate::image::RgbaImage;
use crate::shading::{gooch, pack_rgba8, BACKGROUND};
use crate::volume::Volume;
use glam::Vec3;

/// Step between samples in grid units (DESIGN §4: half a cell).
pub const STEP: f32 = 0.5;
/// Bisection steps after a crossing is found.
pub const REFINEMENTS: u32 = 3;

/// Trilinear interpolation of the sample values at grid position `p`, clamped to the grid.
/// The arithmetic order matches the shader's `sample_volume`.
pub fn trilinear(volume: &Volume, p: Vec3) -> f32 {
    let d = volume.dims();
    let hi = Vec3::new((d[0] - 1) as f32, (d[1] - 1) as f32, (d[2] - 1) as f32);
    let p = p.clamp(Vec3::ZERO, hi);
    let i = [0, 1, 2].map(|a| (p[a].floor() as u32).min(d[a] - 2));
    let f = p - Vec3::new(i[0] as f32, i[1] as f32, i[2] as f32);
    let s = |dx: u32, dy: u32, dz: u32| volume.texel(i[0] + dx, i[1] + dy, i[2] + dz);
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(s(0, 0, 0), s(1, 0, 0), f.x);
    let x10 = lerp(s(0, 1, 0), s(1, 1, 0), f.x);
    let x01 = lerp(s(0, 0, 1), s(1, 0, 1), f.x);
    let x11 = lerp(s(0, 1, 1), s(1, 1, 1), f.x);
    let y0 = lerp(x00, x10, f.y);
    let y1 = lerp(x01, x11, f.y);
    lerp(y0, y1, f.z)
}

/// Entry and exit distances of a ray with the grid box [0, dims-1], if it hits.
pub fn ray_box(origin: Vec3, dir: Vec3, dims: [u32; 3]) -> Option<(f32, f32)> {
    let hi = Vec3::new(
        (dims[0] - 1) as f32,
        (dims[1] - 1) as f32,
        (dims[2] - 1) as f32,
    );
    let inv = dir.recip();
    let t0 = (Vec3::ZERO - origin) * inv;
    let t1 = (hi - origin) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element();
    (near <= far).then_some((near, far))
}

/// Where a ray first crosses the isovalue, in grid units along the ray.
pub fn first_crossing(volume: &Volume, origin: Vec3, dir: Vec3, iso: f32) -> Option<f32> {
    let (near, far) = ray_box(origin, dir, volume.dims())?;
    let steps = ((far - near) / STEP).floor() as u32;
    let at = |t: f32| trilinear(volume, origin + dir * t);
    let mut t_prev = near;
    let mut v_prev = at(t_prev);
    for k in 1..=steps {
        let t = near + k as f32 * STEP;
        let v = at(t);
        if (v < iso) != (v_prev < iso) {
            return Some(refine(&at, iso, t_prev, v_prev, t, v));
        }
        t_prev = t;
        v_prev = v;
    }
    None
}

/// Bisection then linear interpolation between two samples on either side of `iso`.
pub fn refine(
    at: &dyn Fn(f32) -> f32,
    iso: f32,
    mut ta: f32,
    mut va: f32,
    mut tb: f32,
    mut vb: f32,
) -> f32 {
    for _ in 0..REFINEMENTS {
        let tm = 0.5 * (ta + tb);
        let vm = at(tm);
        if (vm < iso) == (va < iso) {
            ta = tm;
            va = vm;
        } else {
            tb = tm;
            vb = vm;
        }
    }
    let denom = vb - va;
    let w = if denom != 0.0 {
        ((iso - va) / denom).clamp(0.0, 1.0)
    } else {
        0.5
    };
    ta + (tb - ta) * w
}

/// Central-difference gradient in grid units.
pub fn gradient(volume: &Volume, p: Vec3) -> Vec3 {
    let s = |q: Vec3| trilinear(volume, q);
    Vec3::new(
        s(p + Vec3::X) - s(p - Vec3::X),
        s(p + Vec3::Y) - s(p - Vec3::Y),
        s(p + Vec3::Z) - s(p - Vec3::Z),
    )
}

/// Colour of a surface hit at grid position `p` seen along grid direction `dir`.
pub fn shade_hit(
    volume: &Volume,
    frame: &GridFrame,
    cam: &GridCamera,
    p: Vec3,
    dir: Vec3,
) -> [f32; 4] {
    // Gradients transform with the inverse of the grid-to-world scale.
    let g = gradient(volume, p) / frame.grid_to_world;
    let n = if g.length_squared() > 0.0 {
        g.normalize()
    } else {
        -dir
    };
    let view = -(dir * frame.grid_to_world).normalize();
    let c = gooch(n, cam.light_world, view);
    [c.x, c.y, c.z, 1.0]
}

/// Renders the isosurface `iso` (in texel units) into a `width`×`height` image.
pub fn render(
    volume: &Volume,
    iso: f32,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
) -> RgbaImage {
    let frame = GridFrame::new(volume.dims(), volume.spacing());
    let cam = GridCamera::new(camera, &frame, width, height);
    let mut img = RgbaImage::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let dir = cam.ray_direction(x, y, width, height);
            let colour = match first_crossing(volume, cam.eye, dir, iso) {
                Some(t) => shade_hit(volume, &frame, &cam, cam.eye + dir * t, dir),
                None => BACKGROUND,
            };
            img.pixels[(y * width + x) as usize] = pack_rgba8(colour);
        }
    }
    img
}
