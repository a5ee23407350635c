//! Face connectivity of a [`TetMesh`]: opposite-face neighbours and the outward boundary.
//!
//! Face `i` of a tet is the face opposite its vertex `i`. Faces are matched by sorting their
//! sorted vertex triples, so the cost is `O(n log n)` with no hashing.

use rayon::prelude::*;

use super::TetMesh;

/// Marks a face without a neighbour in [`TetMesh::neighbours`].
pub const NO_NEIGHBOUR: u32 = u32::MAX;

/// Vertex positions (within a tet) of face `i`, ordered so that the face's normal (right
/// hand rule) points out of a positively oriented tet.
pub const FACE_CORNERS: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

impl TetMesh {
    /// All faces as `(sorted vertex triple, tet * 4 + face)`, sorted.
    fn sorted_faces(&self) -> Vec<([u32; 3], u64)> {
        let mut faces: Vec<([u32; 3], u64)> = self
            .tets
            .par_iter()
            .enumerate()
            .flat_map_iter(|(t, tet)| {
                FACE_CORNERS.iter().enumerate().map(move |(f, corners)| {
                    let mut key = corners.map(|c| tet[c]);
                    key.sort_unstable();
                    (key, t as u64 * 4 + f as u64)
                })
            })
            .collect();
        faces.par_sort_unstable();
        faces
    }

    /// For every tet, the tet across each of its four faces (face `i` is opposite vertex
    /// `i`), or [`NO_NEIGHBOUR`] on the boundary. A face shared by more than two tets
    /// (a non-manifold mesh) links its first two tets only.
    pub fn neighbours(&self) -> Vec<[u32; 4]> {
        let faces = self.sorted_faces();
        let mut result = vec![[NO_NEIGHBOUR; 4]; self.tets.len()];
        let mut i = 0;
        while i < faces.len() {
            let mut j = i + 1;
            while j < faces.len() && faces[j].0 == faces[i].0 {
                j += 1;
            }
            if j - i >= 2 {
                let (a, b) = (faces[i].1, faces[i + 1].1);
                result[(a / 4) as usize][(a % 4) as usize] = (b / 4) as u32;
                result[(b / 4) as usize][(b % 4) as usize] = (a / 4) as u32;
            }
            i = j;
        }
        result
    }

    /// Faces that belong to exactly one tet, with vertices ordered so the normal (right hand
    /// rule) points out of the mesh. Assumes positively oriented tets (see
    /// [`TetMesh::validate`]).
    pub fn boundary_faces(&self) -> Vec<[u32; 3]> {
        let faces = self.sorted_faces();
        let mut result = Vec::new();
        let mut i = 0;
        while i < faces.len() {
            let mut j = i + 1;
            while j < faces.len() && faces[j].0 == faces[i].0 {
                j += 1;
            }
            if j - i == 1 {
                let (t, f) = ((faces[i].1 / 4) as usize, (faces[i].1 % 4) as usize);
                result.push(FACE_CORNERS[f].map(|c| self.tets[t][c]));
            }
            i = j;
        }
        result
    }
}
