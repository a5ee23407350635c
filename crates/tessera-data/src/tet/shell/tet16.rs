//! Tet16 (paper B, Fig. 3): the XOR of the four vertex ids and three neighbour fields
//! `nx[j] = n[j] ^ n[3]`, with `n` sorted as in Tet20: 16 bytes.
//!
//! The fourth neighbour is not stored: the tet a ray came from is the neighbour across the
//! entered face, whose rank is known, and that recovers `n[3]` and with it the others. Entering
//! from the shell, the tet "came from" is [`NO_NEIGHBOUR`], which is exactly what `n` holds
//! there, so the first step of a segment needs no special case.
//!
//! [`NO_NEIGHBOUR`]: crate::tet::topology::NO_NEIGHBOUR

use bytemuck::{Pod, Zeroable};

use super::layouts::{
    entered_tet_vertices, neighbours_by_rank, rank_of, DecodedTet, LayoutKind, TetLayout,
};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Tet16 {
    /// XOR of the four vertex ids.
    pub vx: u32,
    /// `n[j] ^ n[3]` for the neighbours `n` sorted by the id of their opposite vertex.
    pub nx: [u32; 3],
}

/// The tets of a mesh as [`Tet16`].
#[derive(Clone, Debug)]
pub struct Tet16Mesh {
    pub tets: Vec<Tet16>,
}

impl Tet16Mesh {
    pub fn new(tets: &[[u32; 4]], neighbours: &[[u32; 4]]) -> Tet16Mesh {
        Tet16Mesh {
            tets: tets
                .iter()
                .zip(neighbours)
                .map(|(t, n)| {
                    let n = neighbours_by_rank(*t, *n);
                    Tet16 {
                        vx: super::layouts::xor_of(t),
                        nx: [n[0] ^ n[3], n[1] ^ n[3], n[2] ^ n[3]],
                    }
                })
                .collect(),
        }
    }
}

impl TetLayout for Tet16Mesh {
    fn kind(&self) -> LayoutKind {
        LayoutKind::Tet16
    }

    fn bytes_per_tet(&self) -> usize {
        std::mem::size_of::<Tet16>()
    }

    fn tet_count(&self) -> usize {
        self.tets.len()
    }

    fn as_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.tets)
    }

    /// A wrong `came_from` or face gives wrong neighbour ids, which the traversal refuses when
    /// they are out of range.
    fn decode(&self, tet: u32, came_from: u32, entered: [u32; 3]) -> Option<DecodedTet> {
        let stored = self.tets.get(tet as usize)?;
        let vertices = entered_tet_vertices(stored.vx, entered);
        // The entered face is opposite the fourth vertex.
        let last = match rank_of(vertices, 3) {
            3 => came_from,
            r => stored.nx[r] ^ came_from,
        };
        let by_rank = |k: usize| if k == 3 { last } else { stored.nx[k] ^ last };
        Some(DecodedTet {
            vertices,
            neighbours: std::array::from_fn(|i| by_rank(rank_of(vertices, i))),
        })
    }
}
