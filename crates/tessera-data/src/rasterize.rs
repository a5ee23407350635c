//! CPU reference triangle rasterizer: the ground truth for GPU techniques that draw
//! marching-cubes triangles with Vulkan and Gooch shade each fragment.
//!
//! It follows the Vulkan pipeline closely enough that images agree pixel for pixel up to
//! floating-point noise:
//!
//! * Vertices go to clip space with [`Projection::to_clip`] (in `f32`, like a vertex shader).
//! * Triangles are clipped in homogeneous clip space (Sutherland–Hodgman) against `w > 0`,
//!   the near plane `z >= 0` and the far plane `z <= w`, plus a guard band far outside the
//!   viewport that only keeps screen coordinates bounded. A clipped polygon is drawn as a fan.
//! * The viewport maps NDC to pixels as `x = (ndc.x + 1) / 2 * W`, `y = (ndc.y + 1) / 2 * H`
//!   (Vulkan's y points down), and positions are snapped to 1/256 pixel (8 sub-pixel bits).
//! * A pixel is sampled at its centre. Coverage uses edge functions (exact in `f64` on the
//!   snapped grid) with the top-left fill rule, so pixels on an edge shared by two triangles
//!   are drawn exactly once. Triangles are double-sided; zero-area ones draw nothing.
//! * Depth is NDC z interpolated linearly in screen space, tested with LESS against a buffer
//!   cleared to 1.0.
//! * World-space normal and position are interpolated perspective-correctly and shaded by
//!   [`shade_fragment`], the rule the GPU fragment shader implements.
//!
//! [`rasterize_clip_triangles`] applies the same rules to triangles given in clip space, keeping
//! each pixel's depth and triangle index: the contract of the GPU compute rasterizer.

use glam::{DVec3, DVec4, Vec3, Vec4};

use crate::camera::{GridCamera, GridFrame, OrbitCamera, Projection};
use crate::image::RgbaImage;
use crate::mesh::TriangleMesh;
use crate::shading::{gooch, pack_rgba8, BACKGROUND};

/// Sub-pixel precision of snapped screen positions, as in common hardware.
pub const SUBPIXEL_BITS: u32 = 8;
const SUBPIXEL: f64 = (1u32 << SUBPIXEL_BITS) as f64;
/// Smallest clip-space w kept by clipping (the near plane already keeps w well above it).
pub const MIN_W: f64 = 1e-6;
/// Clip-space |x|, |y| limit in multiples of w: a guard band 8 viewports wide and high. Geometry
/// beyond it is off screen anyway; clipping there only bounds the fixed-point coordinates.
pub const GUARD_BAND: f64 = 8.0;

/// What [`rasterize_mesh`] produces; per-pixel vectors are row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct RasterOutput {
    pub image: RgbaImage,
    /// NDC depth of the visible fragment, 1.0 (far) where nothing was drawn.
    pub depth: Vec<f32>,
    /// Whether any fragment was written to the pixel.
    pub coverage: Vec<bool>,
}

/// The colour of a fragment, exactly as the GPU fragment shader computes it.
///
/// `normal_world` is the interpolated world-space normal (not necessarily unit length; it is
/// normalized here, and a zero vector falls back to the view direction). The view direction is
/// `normalize(eye_world - position_world)`; `light_world` is the unit direction towards the
/// light ([`GridCamera::light_world`]). The colour is [`gooch`] (which turns the normal to face
/// the viewer, so either side of a triangle shades the same) packed with alpha 1.
pub fn shade_fragment(
    normal_world: Vec3,
    position_world: Vec3,
    eye_world: Vec3,
    light_world: Vec3,
) -> u32 {
    let view = (eye_world - position_world).normalize_or_zero();
    let n = if normal_world.length_squared() > 0.0 {
        normal_world.normalize()
    } else {
        view
    };
    let c = gooch(n, light_world, view);
    pack_rgba8([c.x, c.y, c.z, 1.0])
}

/// Rasterizes `mesh` (positions and normals in grid coordinates of `frame`) as seen by
/// `camera` into a `width`×`height` image; see the module docs for the conventions.
///
/// Per vertex, the world-space normal is `normalize(normal_grid / frame.grid_to_world)`
/// (normals are grid-space gradients; a zero or missing normal stays zero and so shades with
/// the view direction) and the world-space position is `(p - frame.centre()) * grid_to_world`.
pub fn rasterize_mesh(
    mesh: &TriangleMesh,
    frame: &GridFrame,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
) -> RasterOutput {
    rasterize_counting(mesh, frame, camera, width, height, None)
}

/// [`rasterize_mesh`], also adding to `fragments[pixel]` once per fragment generated there
/// (before the depth test), which lets tests see every coverage decision.
fn rasterize_counting(
    mesh: &TriangleMesh,
    frame: &GridFrame,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
    mut fragments: Option<&mut [u32]>,
) -> RasterOutput {
    let pixel_count = width as usize * height as usize;
    let mut out = RasterOutput {
        image: RgbaImage {
            width,
            height,
            pixels: vec![pack_rgba8(BACKGROUND); pixel_count],
        },
        depth: vec![1.0; pixel_count],
        coverage: vec![false; pixel_count],
    };
    if width == 0 || height == 0 {
        return out;
    }
    let projection = Projection::new(camera, frame, width, height);
    let light = GridCamera::new(camera, frame, width, height).light_world;
    let eye = projection.eye_world;
    let centre = frame.centre();

    // The vertex shader's work, done once per vertex.
    let vertices: Vec<ClipVertex> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let n = mesh.normals.get(i).copied().unwrap_or(Vec3::ZERO) / frame.grid_to_world;
            ClipVertex {
                clip: projection.to_clip(p).as_dvec4(),
                position: ((p - centre) * frame.grid_to_world).as_dvec3(),
                normal: n.normalize_or_zero().as_dvec3(),
            }
        })
        .collect();

    let mut clipper = Clipper::default();
    for t in &mesh.triangles {
        let corners = t.map(|i| vertices[i as usize]);
        clipper.draw(corners, width, height, |index, z, tri, b| {
            if let Some(counts) = fragments.as_deref_mut() {
                counts[index] += 1;
            }
            if z >= out.depth[index] {
                return;
            }
            // Perspective-correct weights: screen barycentrics over clip w, renormalized.
            let q = [0, 1, 2].map(|i| b[i] * tri[i].inv_w);
            let sum = q[0] + q[1] + q[2];
            let mix = |f: fn(&ScreenVertex) -> DVec3| {
                (f(&tri[0]) * q[0] + f(&tri[1]) * q[1] + f(&tri[2]) * q[2]) / sum
            };
            let normal = mix(|v| v.normal).as_vec3();
            let position = mix(|v| v.position).as_vec3();
            out.depth[index] = z;
            out.coverage[index] = true;
            out.image.pixels[index] = shade_fragment(normal, position, eye, light);
        });
    }
    out
}

/// The winding of a triangle on screen, as the rasterizers see it after snapping: the sign of
/// (b - a) × (c - a) on the snapped grid (x right, y down), for the fan triangles of what
/// clipping leaves. Zero-area triangles have none and draw nothing either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScreenWinding {
    Positive,
    Negative,
}

impl ScreenWinding {
    /// The winding of a triangle whose doubled signed area is `area`; `None` for zero (or NaN).
    pub fn of_area(area: f64) -> Option<ScreenWinding> {
        if area > 0.0 {
            Some(ScreenWinding::Positive)
        } else if area < 0.0 {
            Some(ScreenWinding::Negative)
        } else {
            None
        }
    }

    pub fn opposite(self) -> ScreenWinding {
        match self {
            ScreenWinding::Positive => ScreenWinding::Negative,
            ScreenWinding::Negative => ScreenWinding::Positive,
        }
    }
}

/// Rasterizes triangles given directly as clip-space corners (the input of the GPU compute
/// rasterizer) under the rules of [`rasterize_mesh`]. Returns, per pixel (row-major, top row
/// first), the NDC depth and the index in `triangles` of the visible triangle, or `None` where
/// nothing was drawn. Triangles are drawn in order, so at equal depth the lower index stays.
pub fn rasterize_clip_triangles(
    triangles: &[[Vec4; 3]],
    width: u32,
    height: u32,
) -> Vec<Option<(f32, u32)>> {
    rasterize_clip_triangles_hiding(triangles, width, height, None)
}

/// [`rasterize_clip_triangles`], drawing nothing of the fan triangles whose [`ScreenWinding`]
/// is `hidden` (see [`crate::facing::hidden_winding`] for when that leaves the image as it was).
pub fn rasterize_clip_triangles_hiding(
    triangles: &[[Vec4; 3]],
    width: u32,
    height: u32,
    hidden: Option<ScreenWinding>,
) -> Vec<Option<(f32, u32)>> {
    let mut out: Vec<Option<(f32, u32)>> = vec![None; width as usize * height as usize];
    let mut clipper = Clipper {
        hidden,
        ..Clipper::default()
    };
    for (index, t) in triangles.iter().enumerate() {
        let corners = t.map(ClipVertex::bare);
        clipper.draw(corners, width, height, |pixel, z, _, _| {
            if z < out[pixel].map_or(1.0, |(depth, _)| depth) {
                out[pixel] = Some((z, index as u32));
            }
        });
    }
    out
}

/// The polygon [`rasterize_clip_triangles`] fills for one clip-space triangle: what clipping
/// leaves of it, in pixels (snapped to 1/256) with NDC depth in `z`; empty when nothing is left.
/// It is drawn as a fan around its first vertex.
pub fn screen_polygon(clip: &[Vec4; 3], width: u32, height: u32) -> Vec<DVec3> {
    let mut clipper = Clipper::default();
    if !clip_triangle(
        clip.map(ClipVertex::bare),
        &mut clipper.polygon,
        &mut clipper.scratch,
    ) {
        return Vec::new();
    }
    clipper
        .polygon
        .iter()
        .map(|v| {
            let s = ScreenVertex::new(v, width, height);
            DVec3::new(s.x / SUBPIXEL, s.y / SUBPIXEL, s.z)
        })
        .collect()
}

/// Reused storage for clipping one triangle after another.
#[derive(Default)]
struct Clipper {
    polygon: Vec<ClipVertex>,
    scratch: Vec<ClipVertex>,
    /// Fan triangles of this winding draw nothing.
    hidden: Option<ScreenWinding>,
}

impl Clipper {
    /// Clips a triangle, maps it to the screen and calls `fragment(pixel, depth, triangle,
    /// barycentrics)` for each fragment of its fan: `depth` is NDC z clamped to [0, 1] as the
    /// depth test sees it, `triangle` the screen triangle of the fan that produced it.
    fn draw(
        &mut self,
        corners: [ClipVertex; 3],
        width: u32,
        height: u32,
        mut fragment: impl FnMut(usize, f32, &[ScreenVertex; 3], [f64; 3]),
    ) {
        if !clip_triangle(corners, &mut self.polygon, &mut self.scratch) {
            return;
        }
        let screen: Vec<ScreenVertex> = self
            .polygon
            .iter()
            .map(|v| ScreenVertex::new(v, width, height))
            .collect();
        for k in 1..screen.len().saturating_sub(1) {
            let tri = [screen[0], screen[k], screen[k + 1]];
            let area = edge(&tri[0], &tri[1], tri[2].x, tri[2].y);
            if self.hidden.is_some() && ScreenWinding::of_area(area) == self.hidden {
                continue;
            }
            raster_triangle(&tri, width, height, |index, b| {
                let z = (b[0] * tri[0].z + b[1] * tri[1].z + b[2] * tri[2].z) as f32;
                fragment(index, z.clamp(0.0, 1.0), &tri, b);
            });
        }
    }
}

/// A vertex after the vertex shader: clip position and the attributes to interpolate.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ClipVertex {
    clip: DVec4,
    position: DVec3,
    normal: DVec3,
}

impl ClipVertex {
    /// A clip-space position without attributes.
    fn bare(clip: Vec4) -> ClipVertex {
        ClipVertex {
            clip: clip.as_dvec4(),
            position: DVec3::ZERO,
            normal: DVec3::ZERO,
        }
    }

    fn lerp(&self, other: &ClipVertex, t: f64) -> ClipVertex {
        ClipVertex {
            clip: self.clip.lerp(other.clip, t),
            position: self.position.lerp(other.position, t),
            normal: self.normal.lerp(other.normal, t),
        }
    }
}

/// Signed distance of a clip-space point to clip plane `plane`; >= 0 is inside.
fn plane_distance(plane: usize, c: DVec4) -> f64 {
    match plane {
        0 => c.w - MIN_W,
        1 => c.z,
        2 => c.w - c.z,
        3 => GUARD_BAND * c.w - c.x,
        4 => GUARD_BAND * c.w + c.x,
        5 => GUARD_BAND * c.w - c.y,
        _ => GUARD_BAND * c.w + c.y,
    }
}
const PLANE_COUNT: usize = 7;

/// Clips a triangle into `polygon` (a convex fan, first vertex shared). Returns false when
/// nothing is left. `scratch` is reused storage.
fn clip_triangle(
    corners: [ClipVertex; 3],
    polygon: &mut Vec<ClipVertex>,
    scratch: &mut Vec<ClipVertex>,
) -> bool {
    polygon.clear();
    polygon.extend_from_slice(&corners);
    for plane in 0..PLANE_COUNT {
        let inside = polygon
            .iter()
            .filter(|v| plane_distance(plane, v.clip) >= 0.0)
            .count();
        if inside == polygon.len() {
            continue;
        }
        if inside == 0 {
            return false;
        }
        scratch.clear();
        for i in 0..polygon.len() {
            let a = polygon[i];
            let b = polygon[(i + 1) % polygon.len()];
            let (da, db) = (plane_distance(plane, a.clip), plane_distance(plane, b.clip));
            if da >= 0.0 {
                scratch.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                scratch.push(intersect(&a, da, &b, db));
            }
        }
        std::mem::swap(polygon, scratch);
        if polygon.len() < 3 {
            return false;
        }
    }
    true
}

/// Where edge `a`-`b` crosses a plane, given the vertices' signed distances to it. The result
/// does not depend on which way the edge is walked, so triangles sharing an edge that a plane
/// cuts get bit-identical new vertices and stay watertight.
fn intersect(a: &ClipVertex, da: f64, b: &ClipVertex, db: f64) -> ClipVertex {
    if a.clip.to_array() <= b.clip.to_array() {
        a.lerp(b, da / (da - db))
    } else {
        b.lerp(a, db / (db - da))
    }
}

/// A vertex after the perspective divide and viewport transform.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ScreenVertex {
    /// Position in 1/256 pixel units, snapped to integers (stored as f64: all edge-function
    /// arithmetic on them is exact).
    x: f64,
    y: f64,
    /// NDC depth.
    z: f64,
    inv_w: f64,
    position: DVec3,
    normal: DVec3,
}

impl ScreenVertex {
    fn new(v: &ClipVertex, width: u32, height: u32) -> ScreenVertex {
        let inv_w = 1.0 / v.clip.w;
        let snap = |ndc: f64, size: u32| ((ndc + 1.0) * 0.5 * f64::from(size) * SUBPIXEL).round();
        ScreenVertex {
            x: snap(v.clip.x * inv_w, width),
            y: snap(v.clip.y * inv_w, height),
            z: v.clip.z * inv_w,
            inv_w,
            position: v.position,
            normal: v.normal,
        }
    }
}

/// Twice the signed area of (a, b, p) in sub-pixel units; positive when p lies to the right of
/// a→b as seen on screen (x right, y down).
fn edge(a: &ScreenVertex, b: &ScreenVertex, px: f64, py: f64) -> f64 {
    (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)
}

/// Calls `fragment(pixel_index, barycentrics)` for every pixel whose centre the triangle covers
/// under the top-left rule. Barycentrics are screen-space weights of `v[0..3]`, summing to 1.
fn raster_triangle(
    v: &[ScreenVertex; 3],
    width: u32,
    height: u32,
    mut fragment: impl FnMut(usize, [f64; 3]),
) {
    let area = edge(&v[0], &v[1], v[2].x, v[2].y);
    if !(area != 0.0) {
        return; // zero area (or NaN): no fragments, as in Vulkan
    }
    // Orient every edge so the inside is where its edge function is positive.
    let sign = area.signum();
    // Edge i is opposite vertex i.
    let edges = [(1, 2), (2, 0), (0, 1)];
    let top_left = edges.map(|(a, b)| {
        let dx = (v[b].x - v[a].x) * sign;
        let dy = (v[b].y - v[a].y) * sign;
        // With y down and the inside on the right: a top edge is horizontal and runs to the
        // right; a left edge runs upwards.
        dy < 0.0 || (dy == 0.0 && dx > 0.0)
    });

    let lo = |c: f64, size: u32| ((c / SUBPIXEL - 0.5).ceil().max(0.0) as i64).min(size as i64);
    let hi = |c: f64, size: u32| ((c / SUBPIXEL - 0.5).floor().min(size as f64 - 1.0)) as i64;
    let x0 = lo(v[0].x.min(v[1].x).min(v[2].x), width);
    let x1 = hi(v[0].x.max(v[1].x).max(v[2].x), width);
    let y0 = lo(v[0].y.min(v[1].y).min(v[2].y), height);
    let y1 = hi(v[0].y.max(v[1].y).max(v[2].y), height);
    let half = SUBPIXEL / 2.0;
    for y in y0..=y1 {
        let py = y as f64 * SUBPIXEL + half;
        for x in x0..=x1 {
            let px = x as f64 * SUBPIXEL + half;
            let mut e = [0.0; 3];
            let mut inside = true;
            for (i, &(a, b)) in edges.iter().enumerate() {
                e[i] = edge(&v[a], &v[b], px, py);
                let s = e[i] * sign;
                inside &= s > 0.0 || (s == 0.0 && top_left[i]);
            }
            if inside {
                let index = y as usize * width as usize + x as usize;
                fragment(index, e.map(|ei| ei / area));
            }
        }
    }
}

#[cfg(test)]
#[path = "rasterize_tests.rs"]
mod tests;
