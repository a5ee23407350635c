//! The ray-centric 2-D projection of Aman et al. (paper B, §5.2): points are expressed in a
//! basis whose origin is the ray origin and whose third axis is the ray direction, so the ray
//! is the point (0, 0) and every face test becomes a 2-D orientation test.
//!
//! Watertightness comes from deciding everything with one predicate per *edge*
//! ([`ray_left_of`]): the side of a directed edge the ray passes on. It depends only on the
//! edge's two vertices, is evaluated with the lower vertex id first and negated for the other
//! direction, so two tets sharing a face (or an edge) reach the same verdict from both sides,
//! and a ray can never slip between them. A ray exactly on an edge is moved off it by a
//! symbolic perturbation (simulation of simplicity), so it still crosses exactly one face.
//! The GPU will run the same decision structure in `f32`; the canonical operand order is also
//! what keeps it exact there under fused multiply-add.

use glam::DVec3;

/// A vertex in ray space: `x`, `y` across the ray and `z`, the distance along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Projected {
    pub id: u32,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// The orthonormal basis of one ray: `u × v = dir`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayBasis {
    origin: DVec3,
    /// Unit direction.
    dir: DVec3,
    u: DVec3,
    v: DVec3,
}

impl RayBasis {
    /// The basis of the ray `origin + t * dir`; `None` when `dir` has no usable length or
    /// anything is not finite.
    pub fn new(origin: DVec3, dir: DVec3) -> Option<RayBasis> {
        let dir = dir.try_normalize()?;
        if !origin.is_finite() {
            return None;
        }
        let helper = if dir.x.abs() < 0.9 {
            DVec3::X
        } else {
            DVec3::Y
        };
        let u = dir.cross(helper).normalize();
        let v = dir.cross(u);
        Some(RayBasis { origin, dir, u, v })
    }

    /// Vertex `id` at `p` in ray space.
    pub fn project(&self, id: u32, p: DVec3) -> Projected {
        let d = p - self.origin;
        Projected {
            id,
            x: d.dot(self.u),
            y: d.dot(self.v),
            z: d.dot(self.dir),
        }
    }
}

/// True when the ray passes on the left of the directed edge `a → b` in ray space:
/// `cross(a, b) > 0`, the orientation of the triangle `a, b, ray`.
pub(crate) fn ray_left_of(a: &Projected, b: &Projected) -> bool {
    if a.id > b.id {
        return !ray_left_of(b, a);
    }
    let cross = a.x * b.y - a.y * b.x;
    if cross != 0.0 {
        return cross > 0.0;
    }
    // The ray meets the edge's line: decide as if the ray sat at (ε, ε²) for a tiny ε, i.e.
    // by the sign of cross(b - a, (ε, ε²)) = -(b - a).y ε + (b - a).x ε².
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    if dy != 0.0 {
        return dy < 0.0;
    }
    // An edge along the ray (both ends project to one point), or a repeated vertex of a
    // degenerate tet: a fixed answer keeps both sides consistent.
    dx >= 0.0
}

/// Which way a triangle `a, b, c` lets the ray through, if at all.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Crossing {
    /// The ray passes with the triangle counter-clockwise in ray space: its right-hand normal
    /// points along the ray (for a shell face in outward winding: the ray leaves the mesh).
    Along,
    /// Clockwise: the normal faces the ray (for a shell face: the ray enters).
    Against,
    Miss,
}

/// How the ray crosses triangle `a, b, c`, from the three edge predicates.
pub(crate) fn crossing(a: &Projected, b: &Projected, c: &Projected) -> Crossing {
    match (ray_left_of(a, b), ray_left_of(b, c), ray_left_of(c, a)) {
        (true, true, true) => Crossing::Along,
        (false, false, false) => Crossing::Against,
        _ => Crossing::Miss,
    }
}

/// Distance along the ray to where it meets the plane of triangle `a, b, c`: the depths of
/// the corners weighted by the ray's barycentric coordinates in ray space. The corners are
/// taken in vertex id order, so both tets sharing a face get the same bits. A triangle seen
/// edge-on (no area in ray space) gives its nearest corner.
pub(crate) fn crossing_distance(a: &Projected, b: &Projected, c: &Projected) -> f64 {
    let mut p = [a, b, c];
    p.sort_by_key(|q| q.id);
    let cross = |a: &Projected, b: &Projected| a.x * b.y - a.y * b.x;
    let w = [cross(p[1], p[2]), cross(p[2], p[0]), cross(p[0], p[1])];
    let sum = w[0] + w[1] + w[2];
    let t = (w[0] * p[0].z + w[1] * p[1].z + w[2] * p[2].z) / sum;
    if sum != 0.0 && t.is_finite() {
        t
    } else {
        p[0].z.min(p[1].z).min(p[2].z)
    }
}
