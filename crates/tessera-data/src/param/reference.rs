//! CPU reference images of parametric scenes, the ground truth the GPU parametric techniques
//! (paper E) are held to in tests.
//!
//! Every object is tessellated into a uniform parameter grid fine enough that no cell spans more
//! than `max_cell_px` raster pixels (estimated on a coarse grid first), and the triangles are
//! rasterized at pixel centres with a depth buffer, keeping for each pixel the object and the
//! perspective-correct `(u, v)` seen there. A visible pixel is then shaded at that `(u, v)` with
//! the function itself: [`world_position`], [`world_normal`] (finite differences of the
//! world-space surface, [`surface_normal`]) and [`base_colour`], through [`shade`]. With
//! half-pixel cells the triangles stay within ~1e-4 pixel of the true surface for the scenes of
//! the tests, so the reference is the exact "what does the ray through the pixel centre see"
//! image up to pixel centres that lie practically on a silhouette.
//!
//! Shading: two-sided Lambert plus ambient, `base · (AMBIENT + DIFFUSE · max(n·l, 0))` with the
//! normal turned towards the eye. SH glyphs are coloured by direction ([`direction_colour`] of
//! the object-space point), other objects by their own colour.
//!
//! Conventions shared with the GPU: clip space is Vulkan's (y down, depth `z/w` in `[0, 1]`), a
//! point projects to raster pixel `((x/w · 0.5 + 0.5) · W, (y/w · 0.5 + 0.5) · H)`, pixel `(i, j)`
//! is sampled at `(i + 0.5, j + 0.5)`; triangles with a corner behind the eye or outside the
//! depth range are dropped (objects are expected between the near and far planes). With
//! supersampling `k` the raster is `kW × kH` and each image pixel averages its `k × k` samples
//! (background where empty) before rounding to 8 bits.

use glam::{DVec2, Mat4, Vec3};
use rayon::prelude::*;

use super::functions::{surface_normal, ParamFunction};
use super::glyph::direction_colour;
use crate::error::{DataError, Result};
use crate::image::RgbaImage;
use crate::shading::pack_rgba8;

/// Light that reaches surfaces facing away from it.
pub const AMBIENT: f32 = 0.3;
/// Weight of the Lambert term.
pub const DIFFUSE: f32 = 0.7;
/// Default largest screen size of a reference grid cell, in raster pixels.
pub const DEFAULT_MAX_CELL_PX: f32 = 0.5;
/// Most grid cells per axis of one object; beyond it the grid is coarser than asked.
pub const MAX_GRID_SIDE: usize = 4096;
/// Coarse grid used to estimate how fast an object moves across the screen.
const ESTIMATE_SIDE: usize = 64;

/// One object of a scene as the reference sees it.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceObject<'a> {
    pub function: &'a ParamFunction,
    pub object_to_world: Mat4,
    /// Base colour (ignored by SH glyphs, which are coloured by direction).
    pub colour: Vec3,
}

/// Camera and image of a reference render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceView {
    pub world_to_clip: Mat4,
    pub eye: Vec3,
    /// Unit direction towards the light.
    pub light: Vec3,
    pub width: u32,
    pub height: u32,
    /// Samples per image pixel along each axis (1 = none).
    pub supersample: u32,
}

/// `f(u, v)` placed in the world.
pub fn world_position(object: &ReferenceObject, u: f32, v: f32) -> Vec3 {
    object
        .object_to_world
        .transform_point3(object.function.position(u, v))
}

/// Unit normal of the world-space surface (any orientation), `None` where degenerate.
pub fn world_normal(object: &ReferenceObject, u: f32, v: f32) -> Option<Vec3> {
    let domain = object.function.domain();
    surface_normal(|u, v| world_position(object, u, v), &domain, u, v)
}

/// The unshaded colour at `(u, v)`: by direction for SH glyphs, the object's colour otherwise.
pub fn base_colour(object: &ReferenceObject, u: f32, v: f32) -> Vec3 {
    match object.function {
        ParamFunction::ShGlyph(g) => direction_colour(g.position(u, v)),
        _ => object.colour,
    }
}

/// Two-sided Lambert + ambient. A missing normal faces the eye.
pub fn shade(normal: Option<Vec3>, position: Vec3, base: Vec3, eye: Vec3, light: Vec3) -> Vec3 {
    let view = (eye - position).normalize_or_zero();
    let n = normal.unwrap_or(view);
    let n = if n.dot(view) < 0.0 { -n } else { n };
    base * (AMBIENT + DIFFUSE * n.dot(light).max(0.0))
}

/// The colour of object `object` at `(u, v)` seen from `view`.
pub fn shade_point(object: &ReferenceObject, u: f32, v: f32, view: &ReferenceView) -> Vec3 {
    shade(
        world_normal(object, u, v),
        world_position(object, u, v),
        base_colour(object, u, v),
        view.eye,
        view.light,
    )
}

/// What the nearest triangle left at a raster pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceFragment {
    pub depth: f32,
    pub object: u32,
    pub u: f32,
    pub v: f32,
}

/// A projected grid point: raster position, NDC depth, `1/w`; `None` when unusable.
type Projected = Option<(DVec2, f64, f64)>;

fn project(view: &ReferenceView, p: Vec3) -> Projected {
    let (w_px, h_px) = raster_size(view);
    let c = view.world_to_clip * p.extend(1.0);
    let (x, y, z, w) = (c.x as f64, c.y as f64, c.z as f64, c.w as f64);
    if w.is_nan() || w <= 0.0 || !x.is_finite() || !y.is_finite() {
        return None;
    }
    let depth = z / w;
    if !(0.0..1.0).contains(&depth) {
        return None;
    }
    let screen = DVec2::new(
        (x / w * 0.5 + 0.5) * w_px as f64,
        (y / w * 0.5 + 0.5) * h_px as f64,
    );
    Some((screen, depth, 1.0 / w))
}

fn raster_size(view: &ReferenceView) -> (u32, u32) {
    (
        view.width * view.supersample,
        view.height * view.supersample,
    )
}

/// Grid cells `(n_u, n_v)` for `object` so that cells span at most `max_cell_px` pixels where
/// the coarse estimate can see them.
fn grid_size(object: &ReferenceObject, view: &ReferenceView, max_cell_px: f32) -> (usize, usize) {
    let d = object.function.domain();
    let n = ESTIMATE_SIDE;
    let param = |r: [f32; 2], i: usize| r[0] + (r[1] - r[0]) * (i as f32 / n as f32);
    let points: Vec<Projected> = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| (i, j)))
        .map(|(i, j)| project(view, world_position(object, param(d.u, i), param(d.v, j))))
        .collect();
    let (mut along_u, mut along_v) = (0.0_f64, 0.0_f64);
    let at = |i: usize, j: usize| points[j * (n + 1) + i];
    for j in 0..=n {
        for i in 0..=n {
            if let Some((p, _, _)) = at(i, j) {
                if let Some((q, _, _)) = (i < n).then(|| at(i + 1, j)).flatten() {
                    along_u = along_u.max((q - p).length());
                }
                if let Some((q, _, _)) = (j < n).then(|| at(i, j + 1)).flatten() {
                    along_v = along_v.max((q - p).length());
                }
            }
        }
    }
    let side = |px_per_coarse_cell: f64| {
        let cells = (px_per_coarse_cell * n as f64 / f64::from(max_cell_px)).ceil();
        (cells as usize).clamp(n, MAX_GRID_SIDE)
    };
    (side(along_u), side(along_v))
}

/// Rasterizes every object into a `kW × kH` buffer of nearest fragments (`None` = empty).
pub fn reference_fragments(
    objects: &[ReferenceObject],
    view: &ReferenceView,
    max_cell_px: f32,
) -> Result<Vec<Option<ReferenceFragment>>> {
    if view.width == 0 || view.height == 0 || view.supersample == 0 {
        return Err(DataError::Invalid(format!(
            "reference image {}x{} with supersampling {} is empty",
            view.width, view.height, view.supersample
        )));
    }
    if max_cell_px.is_nan() || max_cell_px <= 0.0 {
        return Err(DataError::Invalid(format!(
            "reference cell size must be positive, got {max_cell_px}"
        )));
    }
    let (w, h) = raster_size(view);
    let mut frags: Vec<Option<ReferenceFragment>> = vec![None; (w * h) as usize];
    for (index, object) in objects.iter().enumerate() {
        let (nu, nv) = grid_size(object, view, max_cell_px);
        let d = object.function.domain();
        let param = |r: [f32; 2], i: usize, n: usize| match i {
            0 => r[0],
            _ if i == n => r[1],
            _ => r[0] + (r[1] - r[0]) * (i as f32 / n as f32),
        };
        let grid: Vec<(f32, f32, Projected)> = (0..(nu + 1) * (nv + 1))
            .into_par_iter()
            .map(|k| {
                let (u, v) = (param(d.u, k % (nu + 1), nu), param(d.v, k / (nu + 1), nv));
                (u, v, project(view, world_position(object, u, v)))
            })
            .collect();
        let at = |i: usize, j: usize| &grid[j * (nu + 1) + i];
        for j in 0..nv {
            for i in 0..nu {
                let (c00, c10, c01, c11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                for tri in [[c00, c10, c11], [c00, c11, c01]] {
                    raster_triangle(&tri, index as u32, (w, h), &mut frags);
                }
            }
        }
    }
    Ok(frags)
}

/// Edge function of `p` against edge `a → b`, evaluated from the lexically smaller endpoint so
/// that the two triangles sharing an edge get exactly opposite values and leave no crack.
fn edge(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    let (s, t, sign) = if (a.x, a.y) <= (b.x, b.y) {
        (a, b, 1.0)
    } else {
        (b, a, -1.0)
    };
    sign * ((t.x - s.x) * (p.y - s.y) - (t.y - s.y) * (p.x - s.x))
}

fn raster_triangle(
    tri: &[&(f32, f32, Projected); 3],
    object: u32,
    (w, h): (u32, u32),
    frags: &mut [Option<ReferenceFragment>],
) {
    let [Some(a), Some(b), Some(c)] = tri.map(|t| t.2) else {
        return;
    };
    let pos = [a.0, b.0, c.0];
    let area = edge(pos[0], pos[1], pos[2]);
    if area == 0.0 {
        return;
    }
    let lo = pos[0].min(pos[1]).min(pos[2]);
    let hi = pos[0].max(pos[1]).max(pos[2]);
    let x0 = (lo.x - 0.5).ceil().max(0.0) as i64;
    let y0 = (lo.y - 0.5).ceil().max(0.0) as i64;
    let x1 = ((hi.x - 0.5).floor() as i64).min(i64::from(w) - 1);
    let y1 = ((hi.y - 0.5).floor() as i64).min(i64::from(h) - 1);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let l = [
                edge(pos[1], pos[2], p) / area,
                edge(pos[2], pos[0], p) / area,
                edge(pos[0], pos[1], p) / area,
            ];
            if l.iter().any(|&x| x < 0.0) {
                continue;
            }
            let depth = (l[0] * a.1 + l[1] * b.1 + l[2] * c.1) as f32;
            let slot = &mut frags[(y as u32 * w + x as u32) as usize];
            if slot.is_some_and(|f| f.depth <= depth) {
                continue;
            }
            // Perspective-correct parameters: interpolate u/w, v/w and 1/w linearly.
            let q = [l[0] * a.2, l[1] * b.2, l[2] * c.2];
            let sum = q[0] + q[1] + q[2];
            let interp = |k: usize| {
                let vals = tri.map(|t| if k == 0 { t.0 } else { t.1 } as f64);
                ((q[0] * vals[0] + q[1] * vals[1] + q[2] * vals[2]) / sum) as f32
            };
            *slot = Some(ReferenceFragment {
                depth,
                object,
                u: interp(0),
                v: interp(1),
            });
        }
    }
}

/// The reference image of `objects` seen through `view` in front of `background`, with grid
/// cells of at most `max_cell_px` raster pixels ([`DEFAULT_MAX_CELL_PX`] suits tests).
pub fn render_reference(
    objects: &[ReferenceObject],
    view: &ReferenceView,
    background: [f32; 3],
    max_cell_px: f32,
) -> Result<RgbaImage> {
    let frags = reference_fragments(objects, view, max_cell_px)?;
    let (rw, _) = raster_size(view);
    let k = view.supersample;
    let bg = Vec3::from(background);
    let shaded: Vec<Vec3> = frags
        .par_iter()
        .map(|f| match f {
            Some(f) => shade_point(&objects[f.object as usize], f.u, f.v, view),
            None => bg,
        })
        .collect();
    let pixels = (0..view.width * view.height)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % view.width, i / view.width);
            let mut sum = Vec3::ZERO;
            for sy in 0..k {
                for sx in 0..k {
                    sum += shaded[((y * k + sy) * rw + x * k + sx) as usize];
                }
            }
            let c = sum / (k * k) as f32;
            pack_rgba8([c.x, c.y, c.z, 1.0])
        })
        .collect();
    Ok(RgbaImage {
        width: view.width,
        height: view.height,
        pixels,
    })
}

impl crate::view::View {
    /// This view for the reference renderer.
    pub fn reference(&self) -> ReferenceView {
        ReferenceView {
            world_to_clip: self.world_to_clip,
            eye: self.eye,
            light: self.light,
            width: self.size.0,
            height: self.size.1,
            supersample: self.supersample,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// Orthographic-like view straight down -z: clip = (x / 2, -y / 2, 0.5, 1) for a 2-unit box.
    fn view(size: u32, supersample: u32) -> ReferenceView {
        let world_to_clip = Mat4::from_cols(
            Vec4::new(0.5, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -0.5, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.5, 1.0),
        );
        ReferenceView {
            world_to_clip,
            eye: Vec3::new(0.0, 0.0, 10.0),
            light: Vec3::Z,
            width: size,
            height: size,
            supersample,
        }
    }

    #[test]
    fn sphere_covers_its_disc_and_is_lit_in_the_middle() {
        let sphere = ParamFunction::Sphere;
        let object = ReferenceObject {
            function: &sphere,
            object_to_world: Mat4::IDENTITY,
            colour: Vec3::ONE,
        };
        let v = view(64, 1);
        let img = render_reference(&[object], &v, [0.0; 3], DEFAULT_MAX_CELL_PX).unwrap();
        // The unit disc spans half the 64-pixel view: radius 16 pixels around (32, 32).
        for y in 0..64 {
            for x in 0..64 {
                let r = ((x as f32 + 0.5 - 32.0).powi(2) + (y as f32 + 0.5 - 32.0).powi(2)).sqrt();
                let covered = img.pixels[(y * 64 + x) as usize] != pack_rgba8([0.0, 0.0, 0.0, 1.0]);
                if (r - 16.0).abs() > 0.05 {
                    assert_eq!(covered, r < 16.0, "pixel ({x}, {y}) at radius {r}");
                }
            }
        }
        // Facing the light: ambient + diffuse = 1.
        assert_eq!(img.pixels[32 * 64 + 32] & 0xff, 255);
        let ss = render_reference(&[object], &view(16, 4), [0.0; 3], 1.0).unwrap();
        // The silhouette blends with the background under supersampling.
        assert!(ss.pixels.iter().any(|&p| {
            let r = p & 0xff;
            r > 0 && r < 200
        }));
    }

    #[test]
    fn shading_is_two_sided_and_bad_views_are_errors() {
        let n = Some(Vec3::Z);
        let eye = Vec3::new(0.0, 0.0, -5.0);
        let c = shade(n, Vec3::ZERO, Vec3::ONE, eye, Vec3::NEG_Z);
        assert!((c - Vec3::ONE).length() < 1e-6, "{c}");
        let c = shade(n, Vec3::ZERO, Vec3::ONE, eye, Vec3::Z);
        assert!((c - Vec3::splat(AMBIENT)).length() < 1e-6, "{c}");
        let sphere = ParamFunction::Sphere;
        let object = ReferenceObject {
            function: &sphere,
            object_to_world: Mat4::IDENTITY,
            colour: Vec3::ONE,
        };
        assert!(render_reference(&[object], &view(0, 1), [0.0; 3], 0.5).is_err());
        assert!(render_reference(&[object], &view(8, 1), [0.0; 3], 0.0).is_err());
    }
}
