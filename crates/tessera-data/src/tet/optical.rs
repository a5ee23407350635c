//! CPU reference for interval shading of tetrahedral meshes (paper A, §2 and §3.1): the ground
//! truth for the GPU technique that rasterizes each tet as a depth interval per fragment.
//!
//! Per pixel, the optical depth is the sum over tets of the world-space length of the pixel's
//! ray inside the tet times the tet's absorption colour; the parts of the ray in front of the
//! near clip plane do not count, so the camera may sit inside the mesh. Transmittance follows
//! from Beer–Lambert in a separate post pass ([`transmittance`], [`composite`]).
//!
//! Pixels follow the ray casters' model (see [`crate::camera::GridCamera`]): the centre of
//! pixel (x, y) sees along `forward + sx * right + sy * up` with
//! `sx = (2(x+0.5)/W - 1) tan(fov_x/2)` and `sy = (1 - 2(y+0.5)/H) tan(fov_y/2)`. Meshes are
//! placed in world space by [`MeshFrame`]. Lengths are accumulated in `f64`.

use glam::{DVec3, Mat4, Quat, Vec3};
use rayon::prelude::*;

use super::TetMesh;
use crate::camera::{OrbitCamera, Projection};
use crate::image::RgbaImage;
use crate::shading::pack_rgba8;

/// Absorption of every tet when the mesh has no `absorption` colours.
pub const DEFAULT_ABSORPTION: [f32; 3] = [1.0, 1.0, 1.0];

/// The six edges of a tet as pairs of corner numbers.
const TET_EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// Side of the square pixel tiles that bin tets by their screen rectangles.
const TILE: u32 = 8;

/// Slack, in pixels, added to every tet's screen rectangle against rounding.
const RECT_SLACK: f64 = 1e-3;

/// How a mesh's coordinates map to world space: the centre of its bounding box goes to the
/// origin and its longest side becomes 1, as [`crate::camera::GridFrame`] does for volumes.
/// The GPU techniques for meshes place them the same way (upload [`MeshFrame::mesh_to_world`]
/// or the same centre and scale), so one [`OrbitCamera`] frames meshes of any size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshFrame {
    /// Centre of the mesh's bounding box, in mesh coordinates.
    pub centre: Vec3,
    /// World units per mesh unit: 1 / the longest side of the bounding box.
    pub scale: f32,
}

impl MeshFrame {
    /// The frame of `mesh`. A mesh without vertices, or one whose bounding box has no extent,
    /// keeps scale 1.
    pub fn of(mesh: &TetMesh) -> MeshFrame {
        match mesh.bounds() {
            Some((lo, hi)) => {
                let longest = (hi - lo).max_element();
                let scale = if longest > 0.0 && longest.is_finite() {
                    1.0 / longest
                } else {
                    1.0
                };
                MeshFrame {
                    centre: (lo + hi) * 0.5,
                    scale,
                }
            }
            None => MeshFrame {
                centre: Vec3::ZERO,
                scale: 1.0,
            },
        }
    }

    /// A mesh point in world space: `(p - centre) * scale`.
    pub fn to_world(&self, p: Vec3) -> Vec3 {
        (p - self.centre) * self.scale
    }

    /// [`MeshFrame::to_world`] as a matrix (column-major, points with w = 1); compose it with
    /// [`Projection::world_to_clip`] for the mesh-to-clip transform.
    pub fn mesh_to_world(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            Vec3::splat(self.scale),
            Quat::IDENTITY,
            -self.centre * self.scale,
        )
    }
}

/// View-space depth of the near clip plane the GPU clips at, in world units:
/// [`Projection::near_far`]'s near.
pub fn near_plane(camera: &OrbitCamera) -> f32 {
    Projection::near_far(camera).0
}

/// Entry and exit distances along the ray `origin + t * dir` (`dir` of unit length, so the
/// distances are lengths) of the part of the ray inside the tet with the given corners, in
/// either orientation. The tet is the intersection of the four half-spaces bounded by its
/// face planes; the entry is never below 0 (an origin inside the tet enters at 0). `None`
/// when the ray misses, when the part inside has no length (a ray crossing an edge or a
/// vertex), or when the tet is flat.
///
/// Each face plane is built from its three corners in a fixed (coordinate) order, so two
/// tets sharing a face compute the same plane and a ray leaves one exactly where it enters
/// the other. A ray lying in a face plane belongs to one side only (see
/// [`faces_perturbation`]), so summing over a conforming mesh counts every stretch once.
pub fn ray_tet_interval(origin: Vec3, dir: Vec3, corners: [Vec3; 4]) -> Option<(f32, f32)> {
    interval(
        origin.as_dvec3(),
        dir.as_dvec3(),
        &corners.map(|p| p.as_dvec3()),
    )
    .map(|(a, b)| (a as f32, b as f32))
}

/// [`ray_tet_interval`] in `f64`.
pub(crate) fn interval(origin: DVec3, dir: DVec3, c: &[DVec3; 4]) -> Option<(f64, f64)> {
    let mut t_in = 0.0_f64;
    let mut t_out = f64::INFINITY;
    for apex in 0..4 {
        let mut face = [c[(apex + 1) % 4], c[(apex + 2) % 4], c[(apex + 3) % 4]];
        face.sort_by(|a, b| {
            a.to_array()
                .partial_cmp(&b.to_array())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let normal = (face[1] - face[0]).cross(face[2] - face[0]);
        let apex_side = normal.dot(c[apex] - face[0]);
        if apex_side == 0.0 || !apex_side.is_finite() {
            return None;
        }
        // Outward: away from the corner opposite the face. Inside: dist + t * rate <= 0.
        let outward = if apex_side > 0.0 { -normal } else { normal };
        let dist = outward.dot(origin - face[0]);
        let rate = outward.dot(dir);
        if rate > 0.0 {
            t_out = t_out.min(-dist / rate);
        } else if rate < 0.0 {
            t_in = t_in.max(-dist / rate);
        } else if dist > 0.0 || (dist == 0.0 && !faces_perturbation(outward)) {
            return None;
        }
    }
    (t_out > t_in).then_some((t_in, t_out))
}

/// Tie-break for a ray lying exactly in a face plane (as a pixel ray down a grid line of an
/// axis-aligned mesh does): the ray counts as inside when moving it by the symbolic
/// perturbation `(ε, ε², ε³)` would take it inside, i.e. when the first non-zero component of
/// the outward normal is negative. The two tets sharing a face have exactly opposite normals,
/// so exactly one of them claims such a ray, and of the tets around an edge the ray runs
/// along, exactly one does.
fn faces_perturbation(outward: DVec3) -> bool {
    let first = [outward.x, outward.y, outward.z]
        .into_iter()
        .find(|&c| c != 0.0)
        .unwrap_or(0.0);
    first < 0.0
}

/// The camera in world space with the pixel model of the module documentation, in `f64`.
pub(crate) struct WorldView {
    pub(crate) eye: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    tan_x: f64,
    tan_y: f64,
    near: f64,
    width: f64,
    height: f64,
}

impl WorldView {
    pub(crate) fn new(camera: &OrbitCamera, width: u32, height: u32) -> WorldView {
        let (forward, right, up) = camera.basis();
        let tan_y = f64::from((camera.fov_y_deg.to_radians() * 0.5).tan());
        WorldView {
            eye: camera.eye().as_dvec3(),
            forward: forward.as_dvec3(),
            right: right.as_dvec3(),
            up: up.as_dvec3(),
            tan_x: tan_y * f64::from(width) / f64::from(height.max(1)),
            tan_y,
            near: f64::from(near_plane(camera)).max(1e-9),
            width: f64::from(width),
            height: f64::from(height),
        }
    }

    /// Unit direction of pixel (x, y)'s ray and the distance along it to the near plane.
    pub(crate) fn ray(&self, x: u32, y: u32) -> (DVec3, f64) {
        let sx = (2.0 * (f64::from(x) + 0.5) / self.width - 1.0) * self.tan_x;
        let sy = (1.0 - 2.0 * (f64::from(y) + 0.5) / self.height) * self.tan_y;
        let dir = (self.forward + sx * self.right + sy * self.up).normalize();
        (dir, self.near / dir.dot(self.forward))
    }

    /// View-space depth of a world point.
    fn depth(&self, p: DVec3) -> f64 {
        self.forward.dot(p - self.eye)
    }

    /// Continuous pixel coordinates (pixel (x, y)'s centre is (x + 0.5, y + 0.5)) of a world
    /// point in front of the eye.
    fn to_pixel(&self, p: DVec3) -> (f64, f64) {
        let v = p - self.eye;
        let z = self.forward.dot(v);
        let sx = self.right.dot(v) / z;
        let sy = self.up.dot(v) / z;
        (
            (sx / self.tan_x + 1.0) * 0.5 * self.width,
            (1.0 - sy / self.tan_y) * 0.5 * self.height,
        )
    }

    /// The part of the segment `a`–`b` at or behind the near plane, if any.
    fn clip_segment(&self, a: DVec3, b: DVec3) -> Option<(DVec3, DVec3)> {
        let (za, zb) = (self.depth(a), self.depth(b));
        match (za >= self.near, zb >= self.near) {
            (true, true) => Some((a, b)),
            (false, false) => None,
            (true, false) => Some((a, a + (b - a) * ((self.near - za) / (zb - za)))),
            (false, true) => Some((a + (b - a) * ((self.near - za) / (zb - za)), b)),
        }
    }
}

/// Screen rectangle in continuous pixel coordinates.
#[derive(Debug, Clone, Copy)]
struct Rect {
    min: (f64, f64),
    max: (f64, f64),
}

impl Rect {
    fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.min.0 && x <= self.max.0 && y >= self.min.1 && y <= self.max.1
    }
}

/// Screen rectangle of the part of a tet behind the near plane (the convex hull of its
/// corners there and of its edges' crossings of the plane), `None` when all of it lies in
/// front of the plane.
fn tet_rect(view: &WorldView, c: &[DVec3; 4]) -> Option<Rect> {
    let mut min = (f64::INFINITY, f64::INFINITY);
    let mut max = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut any = false;
    for &(i, j) in &TET_EDGES {
        if let Some((a, b)) = view.clip_segment(c[i], c[j]) {
            for p in [a, b] {
                let (x, y) = view.to_pixel(p);
                min = (min.0.min(x), min.1.min(y));
                max = (max.0.max(x), max.1.max(y));
                any = true;
            }
        }
    }
    any.then_some(Rect {
        min: (min.0 - RECT_SLACK, min.1 - RECT_SLACK),
        max: (max.0 + RECT_SLACK, max.1 + RECT_SLACK),
    })
}

/// Range of pixel indices `0..n` whose centres lie in `[lo, hi]`, if any.
fn pixel_span(lo: f64, hi: f64, n: u32) -> Option<(u32, u32)> {
    if lo.is_nan() || hi.is_nan() {
        return None;
    }
    let first = (lo - 0.5).ceil().max(0.0);
    let last = (hi - 0.5).floor().min(f64::from(n) - 1.0);
    (first <= last).then_some((first as u32, last as u32))
}

/// Tets binned by the pixel tiles their screen rectangles overlap.
struct Bins {
    rects: Vec<Option<Rect>>,
    tiles_x: u32,
    tiles: Vec<Vec<u32>>,
}

impl Bins {
    fn build(corners: &[[DVec3; 4]], view: &WorldView, width: u32, height: u32) -> Bins {
        let rects: Vec<Option<Rect>> = corners.par_iter().map(|c| tet_rect(view, c)).collect();
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        let mut tiles = vec![Vec::new(); (tiles_x * tiles_y) as usize];
        for (t, rect) in rects.iter().enumerate() {
            let Some(r) = rect else { continue };
            let (Some((x0, x1)), Some((y0, y1))) = (
                pixel_span(r.min.0, r.max.0, width),
                pixel_span(r.min.1, r.max.1, height),
            ) else {
                continue;
            };
            for ty in y0 / TILE..=y1 / TILE {
                for tx in x0 / TILE..=x1 / TILE {
                    tiles[(ty * tiles_x + tx) as usize].push(t as u32);
                }
            }
        }
        Bins {
            rects,
            tiles_x,
            tiles,
        }
    }

    /// Tets whose screen rectangle contains the centre of pixel (x, y).
    fn at(&self, x: u32, y: u32) -> impl Iterator<Item = usize> + '_ {
        let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        self.tiles[((y / TILE) * self.tiles_x + x / TILE) as usize]
            .iter()
            .map(|&t| t as usize)
            .filter(move |&t| self.rects[t].is_some_and(|r| r.contains(cx, cy)))
    }
}

/// World-space corners of every tet in `f64`.
fn world_corners(mesh: &TetMesh) -> Vec<[DVec3; 4]> {
    let frame = MeshFrame::of(mesh);
    let world: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|p| frame.to_world(Vec3::from(*p)).as_dvec3())
        .collect();
    mesh.tets
        .iter()
        .map(|t| t.map(|v| world[v as usize]))
        .collect()
}

/// Optical depth per pixel (row-major, rows top to bottom, `width * height` entries): the sum
/// over tets of the world-space length of the pixel's ray inside the tet, counted from the
/// near plane ([`near_plane`]) on, times the tet's absorption colour ([`DEFAULT_ABSORPTION`]
/// when the mesh has none). The mesh is placed by [`MeshFrame::of`]. Panics on vertex indices
/// out of range (run [`TetMesh::validate`] first).
pub fn optical_depth(
    mesh: &TetMesh,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
) -> Vec<[f32; 3]> {
    let absorption = |t: usize| {
        let colour = mesh
            .absorption
            .as_ref()
            .map_or(DEFAULT_ABSORPTION, |a| a[t]);
        Vec3::from(colour).as_dvec3()
    };
    accumulate(mesh, camera, width, height, |t, ray, sum| {
        *sum += (ray.exit - ray.enter) * absorption(t);
    })
}

/// The stretch of one pixel's ray inside one tet: unit direction `dir` from `eye`, entered at
/// distance `enter` (at the near plane or beyond) and left at `exit > enter`.
#[derive(Debug, Clone, Copy)]
pub struct RayStretch {
    pub eye: DVec3,
    pub dir: DVec3,
    pub enter: f64,
    pub exit: f64,
}

/// Per pixel (row-major, rows top to bottom), `add(tet, stretch, accumulator)` for every tet
/// the pixel's ray crosses beyond the near plane, starting from zero; the mesh is placed by
/// [`MeshFrame::of`]. Panics on vertex indices out of range (run [`TetMesh::validate`] first).
pub fn accumulate<F>(
    mesh: &TetMesh,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
    add: F,
) -> Vec<[f32; 3]>
where
    F: Fn(usize, RayStretch, &mut DVec3) + Sync,
{
    accumulate_with(mesh, camera, width, height, add)
        .into_iter()
        .map(|sum: DVec3| sum.as_vec3().to_array())
        .collect()
}

/// [`accumulate`] into any accumulator, starting from its default.
pub fn accumulate_with<A, F>(
    mesh: &TetMesh,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
    add: F,
) -> Vec<A>
where
    A: Default + Clone + Send,
    F: Fn(usize, RayStretch, &mut A) + Sync,
{
    let mut out = vec![A::default(); width as usize * height as usize];
    if width == 0 || height == 0 {
        return out;
    }
    let view = WorldView::new(camera, width, height);
    let corners = world_corners(mesh);
    let bins = Bins::build(&corners, &view, width, height);
    out.par_chunks_mut(width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            let y = y as u32;
            for (x, pixel) in row.iter_mut().enumerate() {
                let x = x as u32;
                let (dir, t_near) = view.ray(x, y);
                for t in bins.at(x, y) {
                    if let Some((enter, exit)) = interval(view.eye, dir, &corners[t]) {
                        let enter = enter.max(t_near);
                        if exit > enter {
                            let stretch = RayStretch {
                                eye: view.eye,
                                dir,
                                enter,
                                exit,
                            };
                            add(t, stretch, pixel);
                        }
                    }
                }
            }
        });
    out
}

/// World-space corners of tet `t` in `f64`, placed as [`accumulate`] places them.
pub fn world_tet(mesh: &TetMesh, frame: &MeshFrame, t: usize) -> [DVec3; 4] {
    mesh.tets[t].map(|v| {
        frame
            .to_world(Vec3::from(mesh.vertices[v as usize]))
            .as_dvec3()
    })
}

/// Beer–Lambert: the fraction of light that passes, `exp(-optical_depth)` per channel.
pub fn transmittance(optical_depth: &[[f32; 3]]) -> Vec<[f32; 3]> {
    optical_depth
        .iter()
        .map(|od| od.map(|d| (-d).exp()))
        .collect()
}

/// The post pass: `background * transmittance` per pixel, opaque, packed with
/// [`pack_rgba8`]. `optical_depth` holds `width * height` pixels as [`optical_depth`] returns
/// them; panics otherwise.
pub fn composite(
    optical_depth: &[[f32; 3]],
    width: u32,
    height: u32,
    background: [f32; 3],
) -> RgbaImage {
    assert_eq!(
        optical_depth.len(),
        width as usize * height as usize,
        "optical depth does not hold {width}x{height} pixels"
    );
    RgbaImage {
        width,
        height,
        pixels: transmittance(optical_depth)
            .iter()
            .map(|t| {
                pack_rgba8([
                    background[0] * t[0],
                    background[1] * t[1],
                    background[2] * t[2],
                    1.0,
                ])
            })
            .collect(),
    }
}

/// Pixels (row-major, rows top to bottom) whose centre lies within `margin_px` pixels of the
/// projection of any tet edge (the part behind the near plane): where GPU rasterization and
/// this reference may legitimately differ. GPU tests compare only the other pixels.
pub fn edge_mask(
    mesh: &TetMesh,
    camera: &OrbitCamera,
    width: u32,
    height: u32,
    margin_px: f32,
) -> Vec<bool> {
    let mut mask = vec![false; width as usize * height as usize];
    if width == 0 || height == 0 {
        return mask;
    }
    let view = WorldView::new(camera, width, height);
    let frame = MeshFrame::of(mesh);
    let world: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|p| frame.to_world(Vec3::from(*p)).as_dvec3())
        .collect();
    let mut edges: Vec<(u32, u32)> = mesh
        .tets
        .iter()
        .flat_map(|t| TET_EDGES.map(|(i, j)| (t[i].min(t[j]), t[i].max(t[j]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let margin = f64::from(margin_px.max(0.0));
    for (i, j) in edges {
        let Some((a, b)) = view.clip_segment(world[i as usize], world[j as usize]) else {
            continue;
        };
        let (a, b) = (view.to_pixel(a), view.to_pixel(b));
        let (Some((x0, x1)), Some((y0, y1))) = (
            pixel_span(a.0.min(b.0) - margin, a.0.max(b.0) + margin, width),
            pixel_span(a.1.min(b.1) - margin, a.1.max(b.1) + margin, height),
        ) else {
            continue;
        };
        for y in y0..=y1 {
            for x in x0..=x1 {
                let p = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                if segment_distance(p, a, b) <= margin {
                    mask[(y * width + x) as usize] = true;
                }
            }
        }
    }
    mask
}

/// Distance from point `p` to the segment `a`–`b` in the plane.
fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (ux, uy) = (b.0 - a.0, b.1 - a.1);
    let (vx, vy) = (p.0 - a.0, p.1 - a.1);
    let len2 = ux * ux + uy * uy;
    let s = if len2 > 0.0 {
        ((vx * ux + vy * uy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (vx - s * ux).hypot(vy - s * uy)
}

#[cfg(test)]
#[path = "optical_tests.rs"]
mod tests;
