//! Tet32 (paper B, Fig. 3): three vertex ids, the XOR of all four and the four neighbours in
//! the mesh's order: 32 bytes.
//!
//! The brief for this layout allowed four plain vertex ids instead; the paper stores three and
//! the XOR field, which is the same size and lets all three layouts share the step that
//! recovers the vertex opposite the entered face (Alg. 2, line 11).

use bytemuck::{Pod, Zeroable};

use super::layouts::{fourth_vertex, xor_of, DecodedTet, LayoutKind, TetLayout};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Tet32 {
    /// The tet's first three vertex ids.
    pub v: [u32; 3],
    /// XOR of the four vertex ids.
    pub vx: u32,
    /// Neighbour across the face opposite vertex `i`, the fourth vertex being
    /// `vx ^ v[0] ^ v[1] ^ v[2]`.
    pub n: [u32; 4],
}

/// The tets of a mesh as [`Tet32`].
#[derive(Clone, Debug)]
pub struct Tet32Mesh {
    pub tets: Vec<Tet32>,
}

impl Tet32Mesh {
    pub fn new(tets: &[[u32; 4]], neighbours: &[[u32; 4]]) -> Tet32Mesh {
        Tet32Mesh {
            tets: tets
                .iter()
                .zip(neighbours)
                .map(|(t, n)| Tet32 {
                    v: [t[0], t[1], t[2]],
                    vx: xor_of(t),
                    n: *n,
                })
                .collect(),
        }
    }
}

impl TetLayout for Tet32Mesh {
    fn kind(&self) -> LayoutKind {
        LayoutKind::Tet32
    }

    fn bytes_per_tet(&self) -> usize {
        std::mem::size_of::<Tet32>()
    }

    fn tet_count(&self) -> usize {
        self.tets.len()
    }

    fn as_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.tets)
    }

    /// The neighbour across a face is the one at the position, in the stored vertex list, of
    /// the vertex opposite it (the paper's "rank of the exit face's index"). A face that is
    /// not the tet's is detected.
    fn decode(&self, tet: u32, _came_from: u32, entered: [u32; 3]) -> Option<DecodedTet> {
        let stored = self.tets.get(tet as usize)?;
        let own = [
            stored.v[0],
            stored.v[1],
            stored.v[2],
            fourth_vertex(stored.vx, stored.v),
        ];
        let vertices = [
            entered[0],
            entered[1],
            entered[2],
            fourth_vertex(stored.vx, entered),
        ];
        let mut neighbours = [0; 4];
        for (slot, v) in neighbours.iter_mut().zip(vertices) {
            *slot = stored.n[own.iter().position(|&o| o == v)?];
        }
        Some(DecodedTet {
            vertices,
            neighbours,
        })
    }
}
