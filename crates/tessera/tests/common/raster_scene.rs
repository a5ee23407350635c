//! A random scene of clip-space triangles for the compute rasterizer's tests: a perspective
//! camera and a few hundred triangles of every kind the rasterizer must handle.

use super::Rng;
use glam::{DVec3, Vec4};

/// A perspective camera like `tessera_data::Projection`: view space x right, y up, z forward.
pub struct Camera {
    pub width: u32,
    pub height: u32,
    pub tan_y: f64,
    pub near: f64,
    pub far: f64,
}

impl Camera {
    pub fn tan_x(&self) -> f64 {
        self.tan_y * f64::from(self.width) / f64::from(self.height)
    }
    /// The view-space point at view depth `d` seen at pixel position (px, py).
    pub fn at_pixel(&self, px: f64, py: f64, d: f64) -> DVec3 {
        let ndc_x = 2.0 * px / f64::from(self.width) - 1.0;
        let ndc_y = 2.0 * py / f64::from(self.height) - 1.0;
        DVec3::new(ndc_x * self.tan_x() * d, -ndc_y * self.tan_y * d, d)
    }
    /// View-space size of one pixel at view depth `d`.
    pub fn pixel_size(&self, d: f64) -> f64 {
        2.0 * self.tan_y * d / f64::from(self.height)
    }
    pub fn to_clip(&self, v: DVec3) -> Vec4 {
        let a = self.far / (self.far - self.near);
        let c = [
            v.x / self.tan_x(),
            -v.y / self.tan_y,
            a * (v.z - self.near),
            v.z,
        ];
        Vec4::from_array(c.map(|x| x as f32))
    }
}

/// A triangle around the pixel (px, py) at depth d, `size` pixels across, its corners spread
/// in depth by up to `depth_spread` view units.
pub fn triangle(
    cam: &Camera,
    rng: &mut Rng,
    centre: DVec3,
    size: f64,
    depth_spread: f64,
) -> [Vec4; 3] {
    let base = cam.at_pixel(centre.x, centre.y, centre.z);
    let r = size * cam.pixel_size(centre.z) * 0.5;
    [0, 1, 2].map(|_| {
        let angle = rng.range(0.0, std::f64::consts::TAU);
        let radius = r * rng.range(0.3, 1.0);
        let offset = DVec3::new(
            radius * angle.cos(),
            radius * angle.sin(),
            rng.range(-depth_spread, depth_spread),
        );
        cam.to_clip(base + offset)
    })
}

/// A few hundred triangles: small and medium ones (overlapping, some partly off screen), some
/// crossing the near plane or reaching behind the eye, some crossing the far plane, repeated
/// ones, degenerate ones and ones wholly outside.
pub fn random_scene(cam: &Camera, rng: &mut Rng) -> Vec<[Vec4; 3]> {
    let (w, h) = (f64::from(cam.width), f64::from(cam.height));
    let mut tris = Vec::new();
    let centre = |rng: &mut Rng, d0: f64, d1: f64| {
        DVec3::new(
            rng.range(-0.1 * w, 1.1 * w),
            rng.range(-0.1 * h, 1.1 * h),
            rng.range(d0, d1),
        )
    };
    for _ in 0..300 {
        let c = centre(rng, 1.0, 6.0);
        let size = rng.range(1.0, 8.0);
        tris.push(triangle(cam, rng, c, size, 0.02));
    }
    for _ in 0..250 {
        let c = centre(rng, 1.0, 6.0);
        let size = rng.range(10.0, 80.0);
        tris.push(triangle(cam, rng, c, size, 0.5));
    }
    for _ in 0..40 {
        // Near the near plane with corners spread to either side of it, some behind the eye.
        let c = centre(rng, cam.near * 0.8, cam.near * 1.6);
        let size = rng.range(20.0, 150.0);
        tris.push(triangle(cam, rng, c, size, 1.2));
    }
    for _ in 0..30 {
        let c = centre(rng, cam.far - 1.0, cam.far + 0.5);
        let size = rng.range(10.0, 80.0);
        tris.push(triangle(cam, rng, c, size, 2.0));
    }
    // Exact copies drawn later: equal depths, where the lower index must stay.
    for k in 0..20 {
        tris.push(tris[300 + 7 * k]);
    }
    // Degenerate: a repeated corner, collinear corners, one point.
    let p = |x: f64, y: f64, d: f64| cam.to_clip(cam.at_pixel(x, y, d));
    tris.push([p(10.0, 10.0, 2.0), p(10.0, 10.0, 2.0), p(60.0, 40.0, 2.0)]);
    tris.push([p(10.0, 50.0, 2.0), p(30.0, 60.0, 2.0), p(50.0, 70.0, 2.0)]);
    tris.push([p(80.0, 80.0, 2.0); 3]);
    // Wholly off screen, wholly behind the eye, wholly beyond the far plane.
    tris.push([
        p(-90.0, 10.0, 2.0),
        p(-30.0, 50.0, 2.0),
        p(-60.0, 90.0, 3.0),
    ]);
    let behind = |x: f64, y: f64| cam.to_clip(DVec3::new(x, y, -1.0));
    tris.push([behind(0.0, 0.0), behind(1.0, 0.0), behind(0.0, 1.0)]);
    tris.push([
        p(20.0, 20.0, 9.0),
        p(200.0, 30.0, 9.5),
        p(90.0, 150.0, 10.0),
    ]);
    tris
}
