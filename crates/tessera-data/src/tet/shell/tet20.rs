//! Tet20 (paper B, Fig. 3): the XOR of the four vertex ids and the four neighbours sorted by
//! the id of the vertex opposite each: 20 bytes.

use bytemuck::{Pod, Zeroable};

use super::layouts::{
    entered_tet_vertices, neighbours_by_rank, rank_of, DecodedTet, LayoutKind, TetLayout,
};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Tet20 {
    /// XOR of the four vertex ids.
    pub vx: u32,
    /// `n[k]`: the neighbour across the face opposite the vertex with the k-th smallest id.
    pub n: [u32; 4],
}

/// The tets of a mesh as [`Tet20`].
#[derive(Clone, Debug)]
pub struct Tet20Mesh {
    pub tets: Vec<Tet20>,
}

impl Tet20Mesh {
    pub fn new(tets: &[[u32; 4]], neighbours: &[[u32; 4]]) -> Tet20Mesh {
        Tet20Mesh {
            tets: tets
                .iter()
                .zip(neighbours)
                .map(|(t, n)| Tet20 {
                    vx: super::layouts::xor_of(t),
                    n: neighbours_by_rank(*t, *n),
                })
                .collect(),
        }
    }
}

impl TetLayout for Tet20Mesh {
    fn kind(&self) -> LayoutKind {
        LayoutKind::Tet20
    }

    fn bytes_per_tet(&self) -> usize {
        std::mem::size_of::<Tet20>()
    }

    fn tet_count(&self) -> usize {
        self.tets.len()
    }

    fn as_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.tets)
    }

    /// Without vertex ids the layout cannot tell a wrong face; the ids it then yields are
    /// wrong but in no way unsafe.
    fn decode(&self, tet: u32, _came_from: u32, entered: [u32; 3]) -> Option<DecodedTet> {
        let stored = self.tets.get(tet as usize)?;
        let vertices = entered_tet_vertices(stored.vx, entered);
        Some(DecodedTet {
            vertices,
            neighbours: std::array::from_fn(|i| stored.n[rank_of(vertices, i)]),
        })
    }
}
