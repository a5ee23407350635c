//! The shell: faces that belong to one tet only, each with that tet, from the neighbour table.

use crate::tet::topology::{FACE_CORNERS, NO_NEIGHBOUR};

/// A boundary triangle of the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShellFace {
    /// Vertex ids ordered so the normal (right hand rule) points out of the mesh.
    pub vertices: [u32; 3],
    /// The tet behind the face, where marching starts when a ray enters through it.
    pub tet: u32,
    /// Which face of that tet it is (the face opposite the tet's vertex `face`).
    pub face: u8,
}

/// Every face without a neighbour, in tet order. Assumes positively oriented tets (the
/// winding comes from [`FACE_CORNERS`]). A face shared by three tets or more (non-manifold)
/// counts as shell for the tets [`crate::tet::TetMesh::neighbours`] left unlinked.
pub fn shell_faces(tets: &[[u32; 4]], neighbours: &[[u32; 4]]) -> Vec<ShellFace> {
    tets.iter()
        .zip(neighbours)
        .enumerate()
        .flat_map(|(t, (tet, across))| {
            (0..4)
                .filter(|&f| across[f] == NO_NEIGHBOUR)
                .map(move |f| ShellFace {
                    vertices: FACE_CORNERS[f].map(|c| tet[c]),
                    tet: t as u32,
                    face: f as u8,
                })
        })
        .collect()
}
