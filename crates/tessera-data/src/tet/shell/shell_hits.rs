//! Where a ray's line crosses the shell, found by brute force over the shell faces with the
//! same edge predicates marching uses, so a ray that enters through a face starts marching in
//! a state the next steps agree with. It stands in for the shell BVH: one pass over the faces
//! answers every trace of Alg. 1 for this ray.

use super::projection::{crossing, crossing_distance, Crossing, RayBasis};
use super::ShellMesh;

/// A shell face the ray's line crosses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShellHit {
    /// Index into [`ShellMesh::faces`].
    pub face: u32,
    /// Signed distance along the ray (negative behind the origin).
    pub t: f64,
    /// The ray leaves the mesh here (a back face, the only kind a front-face-culled trace
    /// sees); otherwise it enters.
    pub leaves: bool,
}

/// Every shell crossing of the ray's line, sorted by distance; at equal distance exits come
/// first, so where two components touch, the first one closes before the next opens.
pub(crate) fn shell_hits(shell: &ShellMesh, basis: &RayBasis) -> Vec<ShellHit> {
    let mut hits: Vec<ShellHit> = shell
        .faces
        .iter()
        .enumerate()
        .filter_map(|(i, face)| {
            let [a, b, c] = face
                .vertices
                .map(|v| basis.project(v, shell.world[v as usize]));
            let leaves = match crossing(&a, &b, &c) {
                Crossing::Along => true,
                Crossing::Against => false,
                Crossing::Miss => return None,
            };
            Some(ShellHit {
                face: i as u32,
                t: crossing_distance(&a, &b, &c),
                leaves,
            })
        })
        .collect();
    hits.sort_by(|p, q| p.t.total_cmp(&q.t).then(q.leaves.cmp(&p.leaves)));
    hits
}
