//! Which triangles of a closed isosurface no pixel can show: those whose winding on screen
//! says they face away from the region the view rays start in.
//!
//! When every sample on the grid's boundary lies on one side of the isovalue, marching cubes'
//! surface never reaches the boundary: it is closed, and (its triangles wound alike) it
//! separates the cells below the isovalue from those at or above it. When, besides, the whole
//! grid lies in front of the near plane, every view ray enters the grid in the boundary's
//! region, so the first surface it meets is seen from that side. A triangle turned the other
//! way is never nearest along a ray, and a rasterizer may skip it: the image stays the same
//! but for pixels where snapping turns a sliver around. That halves the triangles the raster
//! walk visits on a closed surface.

use crate::rasterize::ScreenWinding;
use crate::volume::Volume;
use glam::{DMat4, DVec4, Mat4};

/// Marching cubes' winding: (p1 - p0) × (p2 - p0) of each triangle points towards the samples
/// below the isovalue (its normals' side; checked by a test here).
const CROSS_POINTS_BELOW: bool = true;

/// The lowest and highest sample on the grid's six faces, as [`Volume::texel`] gives them (a
/// volume's samples are finite).
pub fn boundary_range(volume: &Volume) -> (f32, f32) {
    let [nx, ny, nz] = volume.dims();
    let mut range = (f32::INFINITY, f32::NEG_INFINITY);
    let mut take = |x, y, z| {
        let v = volume.texel(x, y, z);
        range = (range.0.min(v), range.1.max(v));
    };
    for z in 0..nz {
        for y in 0..ny {
            let all_x = z == 0 || z == nz - 1 || y == 0 || y == ny - 1;
            if all_x {
                (0..nx).for_each(|x| take(x, y, z));
            } else {
                take(0, y, z);
                take(nx - 1, y, z);
            }
        }
    }
    range
}

/// The side of an isovalue a grid's boundary samples lie on, when they all lie on one: the
/// surface at that isovalue is then closed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundarySide {
    /// Every boundary sample below the isovalue.
    Below,
    /// Every boundary sample at or above it.
    AtOrAbove,
}

/// Where the boundary samples spanning `boundary` ([`boundary_range`]) lie against `iso`
/// (texel units); `None` when they straddle it (the surface may end on the boundary).
pub fn boundary_side(boundary: (f32, f32), iso: f32) -> Option<BoundarySide> {
    // A corner is below when its value is below the isovalue (as marching cubes classifies).
    if boundary.1 < iso {
        Some(BoundarySide::Below)
    } else if boundary.0 >= iso {
        Some(BoundarySide::AtOrAbove)
    } else {
        None
    }
}

/// The screen winding of the triangles no pixel shows, for marching cubes' closed surface on
/// a grid of `dims` samples whose boundary lies on `side` of the isovalue, seen through
/// `grid_to_clip` (grid coordinates, sample (x, y, z) at (x, y, z), to Vulkan clip space).
/// `None` when every triangle may show: part of the grid lies behind the near plane, or the
/// projection has no eye point (parallel).
pub fn hidden_winding(
    grid_to_clip: Mat4,
    dims: [u32; 3],
    side: BoundarySide,
) -> Option<ScreenWinding> {
    let m = grid_to_clip.as_dmat4();
    let far = dims.map(|d| f64::from(d.max(1) - 1));
    for c in 0..8 {
        let corner = DVec4::new(
            if c & 1 == 0 { 0.0 } else { far[0] },
            if c & 2 == 0 { 0.0 } else { far[1] },
            if c & 4 == 0 { 0.0 } else { far[2] },
            1.0,
        );
        let clip = m * corner;
        if !(clip.w > 0.0 && clip.z > 0.0) {
            return None;
        }
    }
    let facing = facing_eye_winding(&m)?;
    // The triangles seen first face the eye with the side the rays start in.
    let seen = if (side == BoundarySide::Below) == CROSS_POINTS_BELOW {
        facing
    } else {
        facing.opposite()
    };
    Some(seen.opposite())
}

/// The screen winding of triangles (in front of the eye) whose (p1 - p0) × (p2 - p0) points
/// towards the eye, for the projection `m`.
///
/// Clip x, y and w vanish together at the eye's homogeneous point e, so for any three points
/// det(x y w of M q0, M q1, M q2) = c · det(q0, q1, q2, e) for one constant c, and for grid
/// points p det([p0 1], [p1 1], [p2 1], e) = -e.w ((p1 - p0) × (p2 - p0)) · (eye - p0). With
/// every w positive, the first determinant's sign is the screen area's.
fn facing_eye_winding(m: &DMat4) -> Option<ScreenWinding> {
    let rows = [m.row(0), m.row(1), m.row(3)];
    let e = generalized_cross(rows);
    if e.w.abs() <= 1e-12 * e.length() {
        return None;
    }
    // c from the three basis vectors that leave out e's largest component.
    let skip = (0..4)
        .max_by(|&a, &b| e[a].abs().total_cmp(&e[b].abs()))
        .unwrap_or(3);
    let q: Vec<DVec4> = (0..4)
        .filter(|&i| i != skip)
        .map(|i| DVec4::from_array(std::array::from_fn(|j| f64::from(u8::from(i == j)))))
        .collect();
    let projected = |v: DVec4| glam::DVec3::new(rows[0].dot(v), rows[1].dot(v), rows[2].dot(v));
    let left =
        glam::DMat3::from_cols(projected(q[0]), projected(q[1]), projected(q[2])).determinant();
    let right = DMat4::from_cols(q[0], q[1], q[2], e).determinant();
    let c = left / right;
    // Facing the eye: the second determinant has the sign of -e.w.
    ScreenWinding::of_area(-c * e.w)
}

/// The vector orthogonal to three 4-vectors: its components are their signed 3×3 minors.
fn generalized_cross(r: [DVec4; 3]) -> DVec4 {
    let minor = |skip: usize| {
        let cols: Vec<usize> = (0..4).filter(|&i| i != skip).collect();
        glam::DMat3::from_cols_array(&[
            r[0][cols[0]],
            r[1][cols[0]],
            r[2][cols[0]],
            r[0][cols[1]],
            r[1][cols[1]],
            r[2][cols[1]],
            r[0][cols[2]],
            r[1][cols[2]],
            r[2][cols[2]],
        ])
        .determinant()
    };
    DVec4::new(minor(0), -minor(1), minor(2), -minor(3))
}

#[cfg(test)]
#[path = "facing_tests.rs"]
mod tests;
