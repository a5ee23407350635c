//! CPU reference for integrating a per-vertex scalar field through a tet mesh with a transfer
//! function: the ground truth for interval shading's scalar modes.
//!
//! The scalar is linear inside each tet (barycentric interpolation of its corners' values), so
//! along a ray's stretch through a tet it runs linearly from its value at the entry to its
//! value at the exit, and the integral of a piecewise-linear table over that stretch is its
//! mean over [s_entry, s_exit] ([`IntegrandTable::average`]) times the stretch's length. The
//! maximum of a linear function over the stretch is at one end.

use glam::{DMat3, DVec3};

use super::optical::{accumulate, world_tet, MeshFrame, RayStretch};
use super::TetMesh;
use crate::camera::OrbitCamera;
use crate::error::{DataError, Result};
use crate::transfer::{IntegrandTable, ScalarMode};

/// Smallest and largest finite vertex scalar, `None` without scalars.
pub fn scalar_range(mesh: &TetMesh) -> Option<(f32, f32)> {
    let values = mesh.scalars.as_ref()?;
    values
        .iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, &v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// The range the vertex scalars are mapped to [0, 1] with: `range`, or the mesh's own; an
/// error naming `what` when the mesh has no scalars or the range is not finite.
pub fn mapping_range(mesh: &TetMesh, range: Option<(f32, f32)>, what: &str) -> Result<(f32, f32)> {
    if mesh.scalars.is_none() {
        return Err(DataError::Invalid(format!(
            "{what}: the mesh has no per-vertex scalars to integrate"
        )));
    }
    match range.or_else(|| scalar_range(mesh)) {
        Some(r) if r.0.is_finite() && r.1.is_finite() => Ok(r),
        _ => Err(DataError::Invalid(format!(
            "{what}: no finite scalar range"
        ))),
    }
}

/// `value` mapped to [0, 1] over `(lo, hi)` and clamped there; a range without extent maps
/// everything to 0. The GPU maps each tet corner the same way (`proxy.glsl`).
pub fn normalize_scalar(value: f32, (lo, hi): (f32, f32)) -> f32 {
    let extent = hi - lo;
    if extent > 0.0 {
        ((value - lo) / extent).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The vertex scalars mapped to [0, 1] over `range` (the mesh's own range by default), as
/// [`normalize_scalar`] maps them. `what` names the mesh in errors.
pub fn normalized_scalars(
    mesh: &TetMesh,
    range: Option<(f32, f32)>,
    what: &str,
) -> Result<Vec<f32>> {
    let range = mapping_range(mesh, range, what)?;
    let values = mesh.scalars.as_deref().unwrap_or_default();
    Ok(values.iter().map(|&v| normalize_scalar(v, range)).collect())
}

/// A tet's corners and the map from a point to its barycentric weights of corners 1..3.
pub(crate) struct TetLinear {
    origin: DVec3,
    to_barycentric: DMat3,
    values: [f64; 4],
}

impl TetLinear {
    fn new(corners: [DVec3; 4], values: [f64; 4]) -> TetLinear {
        let edges = DMat3::from_cols(
            corners[1] - corners[0],
            corners[2] - corners[0],
            corners[3] - corners[0],
        );
        TetLinear {
            origin: corners[0],
            to_barycentric: edges.inverse(),
            values,
        }
    }

    /// The scalar at the two ends of `stretch`: where the ray enters and leaves the tet.
    pub(crate) fn at_ends(&self, stretch: &RayStretch) -> (f64, f64) {
        (
            self.at(stretch.eye + stretch.dir * stretch.enter),
            self.at(stretch.eye + stretch.dir * stretch.exit),
        )
    }

    /// The scalar's gradient, exact for the linear scalar; zero for a flat tet.
    pub(crate) fn gradient(&self) -> DVec3 {
        let v = self.values;
        let rise = DVec3::new(v[1] - v[0], v[2] - v[0], v[3] - v[0]);
        // s(p) = v0 + rise · B (p − origin), B the barycentric map: ∇s = Bᵀ rise.
        let gradient = self.to_barycentric.transpose() * rise;
        if gradient.is_finite() {
            gradient
        } else {
            DVec3::ZERO
        }
    }

    fn at(&self, p: DVec3) -> f64 {
        let w = self.to_barycentric * (p - self.origin);
        let w0 = 1.0 - w.x - w.y - w.z;
        w0 * self.values[0] + w.x * self.values[1] + w.y * self.values[2] + w.z * self.values[3]
    }
}

/// The linear scalar of every tet in world space (placed by [`MeshFrame::of`]), from one
/// normalized value per vertex.
pub(crate) fn tet_linears(mesh: &TetMesh, normalized: &[f32]) -> Vec<TetLinear> {
    let frame = MeshFrame::of(mesh);
    (0..mesh.tets.len())
        .map(|t| {
            let values = mesh.tets[t].map(|v| f64::from(normalized[v as usize]));
            TetLinear::new(world_tet(mesh, &frame, t), values)
        })
        .collect()
}

/// Per pixel (row-major, top row first): for [`ScalarMode::Absorption`] and
/// [`ScalarMode::Emission`] the sum over tets of the stretch's length times the table's mean
/// over the scalar's run along it; for [`ScalarMode::Maximum`] `[largest scalar, 1, 0]` where
/// a tet is crossed and zeros elsewhere. `normalized` holds one value in [0, 1] per vertex
/// ([`normalized_scalars`]).
pub fn integrate_scalar(
    mesh: &TetMesh,
    normalized: &[f32],
    camera: &OrbitCamera,
    (width, height): (u32, u32),
    table: &IntegrandTable,
    mode: ScalarMode,
) -> Vec<[f32; 3]> {
    let linear = tet_linears(mesh, normalized);
    accumulate(mesh, camera, width, height, |t, ray: RayStretch, sum| {
        let (s_in, s_out) = linear[t].at_ends(&ray);
        match mode {
            ScalarMode::Maximum => {
                *sum = DVec3::new(sum.x.max(s_in).max(s_out), 1.0, 0.0);
            }
            _ => *sum += table.average(s_in, s_out) * (ray.exit - ray.enter),
        }
    })
}

/// The image of the maximum mode: the table's colour at each pixel's largest scalar, the
/// background where no tet was crossed.
pub fn maximum_colours(
    maxima: &[[f32; 3]],
    table: &IntegrandTable,
    background: [f32; 3],
) -> Vec<[f32; 3]> {
    maxima
        .iter()
        .map(|m| {
            if m[1] > 0.0 {
                table.value(f64::from(m[0])).as_vec3().to_array()
            } else {
                background
            }
        })
        .collect()
}

#[cfg(test)]
#[path = "scalar_integral_tests.rs"]
mod tests;
