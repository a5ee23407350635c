//! What the three compact tet layouts of paper B (§5.1) have in common: the XOR of a tet's four
//! vertex ids (`vx`), from which any three recover the fourth, and a decoder that, given the
//! face a ray entered through and the tet it came from, yields the tet's four vertices and the
//! tet across each face.

use crate::error::{DataError, Result};

use super::tet16::Tet16Mesh;
use super::tet20::Tet20Mesh;
use super::tet32::Tet32Mesh;

/// Which layout of [`TetLayout`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayoutKind {
    Tet32,
    Tet20,
    Tet16,
}

impl LayoutKind {
    pub const ALL: [LayoutKind; 3] = [LayoutKind::Tet32, LayoutKind::Tet20, LayoutKind::Tet16];

    pub fn name(self) -> &'static str {
        match self {
            LayoutKind::Tet32 => "tet32",
            LayoutKind::Tet20 => "tet20",
            LayoutKind::Tet16 => "tet16",
        }
    }

    pub fn parse(text: &str) -> Result<LayoutKind> {
        LayoutKind::ALL
            .into_iter()
            .find(|k| k.name() == text)
            .ok_or_else(|| {
                DataError::Invalid(format!("layout '{text}': choose tet32, tet20 or tet16"))
            })
    }
}

/// A tet as a marching step sees it: the three vertices of the face the ray entered through
/// (in the order given), then the fourth; `neighbours[i]` is the tet across the face opposite
/// `vertices[i]`, [`crate::tet::topology::NO_NEIGHBOUR`] on the shell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DecodedTet {
    pub vertices: [u32; 4],
    pub neighbours: [u32; 4],
}

/// A compact array of tets that marching reads.
pub trait TetLayout: Sync + Send {
    fn kind(&self) -> LayoutKind;

    /// Bytes one tet takes (the array's only per-tet storage).
    fn bytes_per_tet(&self) -> usize;

    fn tet_count(&self) -> usize;

    /// The array as a GPU reads it: the layout's `#[repr(C)]` structs back to back, 32-bit
    /// words only.
    fn as_bytes(&self) -> &[u8];

    /// Tet `tet` entered through the face with vertex ids `entered` from tet `came_from` (the
    /// tet across that face, [`crate::tet::topology::NO_NEIGHBOUR`] when entering from the
    /// shell). `None` when the input cannot belong to the tet (an id out of range, or a face
    /// that is not the tet's where the layout can tell): a corrupt step the traversal's guard
    /// counts. Where the layout cannot tell, a wrong input gives wrong ids, never a panic.
    fn decode(&self, tet: u32, came_from: u32, entered: [u32; 3]) -> Option<DecodedTet>;
}

/// Layout `kind` of `tets` with their `neighbours` (as [`crate::tet::TetMesh::neighbours`]).
pub fn build_layout(
    kind: LayoutKind,
    tets: &[[u32; 4]],
    neighbours: &[[u32; 4]],
) -> Box<dyn TetLayout> {
    match kind {
        LayoutKind::Tet32 => Box::new(Tet32Mesh::new(tets, neighbours)),
        LayoutKind::Tet20 => Box::new(Tet20Mesh::new(tets, neighbours)),
        LayoutKind::Tet16 => Box::new(Tet16Mesh::new(tets, neighbours)),
    }
}

/// XOR of all ids.
pub(crate) fn xor_of(ids: &[u32]) -> u32 {
    ids.iter().fold(0, |acc, &v| acc ^ v)
}

/// The fourth vertex of a tet whose XOR field is `vx`, given the other three.
pub(crate) fn fourth_vertex(vx: u32, face: [u32; 3]) -> u32 {
    vx ^ xor_of(&face)
}

/// The four vertices of a tet entered through `entered`, the vertex opposite it last,
/// recovered from the tet's XOR field `vx` (Tet20 and Tet16 store no vertex ids).
pub(crate) fn entered_tet_vertices(vx: u32, entered: [u32; 3]) -> [u32; 4] {
    [
        entered[0],
        entered[1],
        entered[2],
        fourth_vertex(vx, entered),
    ]
}

/// Rank of `ids[i]` among the four ids (ascending; equal ids, which only degenerate tets
/// have, ranked by position). Tet20 and Tet16 store neighbours in this order, so the rank of
/// the vertex opposite a face picks the neighbour across it without storing vertex ids.
pub(crate) fn rank_of(ids: [u32; 4], i: usize) -> usize {
    (0..4)
        .filter(|&j| ids[j] < ids[i] || (ids[j] == ids[i] && j < i))
        .count()
}

/// A tet's neighbours sorted by the rank of the vertex opposite each.
pub(crate) fn neighbours_by_rank(tet: [u32; 4], neighbours: [u32; 4]) -> [u32; 4] {
    let mut sorted = [0; 4];
    for i in 0..4 {
        sorted[rank_of(tet, i)] = neighbours[i];
    }
    sorted
}
