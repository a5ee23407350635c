//! Marching-cubes case tables, derived at first use from the cube's geometry instead of
//! being written out by hand, so every entry follows from the conventions below and the
//! tests can check the rules rather than literal rows.
//!
//! # Conventions
//!
//! * **Corners.** Corner `i` (0..8) of a cell sits at offset
//!   `(i & 1, (i >> 1) & 1, (i >> 2) & 1)` from the cell's minimum corner: bit 0 is x,
//!   bit 1 is y, bit 2 is z ([`CORNER_OFFSETS`]).
//! * **Edges.** Edges 0-3 run along x, 4-7 along y, 8-11 along z ([`EDGE_AXIS`]).
//!   Within an axis group the two remaining coordinate bits of the edge's start corner
//!   count up, lower axis first: edge 1 runs from `(0,1,0)` to `(1,1,0)`, edge 6 from
//!   `(0,0,1)` to `(0,1,1)`. [`EDGE_CORNERS`] lists `[start, end]`; the start corner is
//!   always the one with the smaller coordinate.
//! * **Faces.** Face `f` (0..6) is the face whose coordinate along axis `f / 2` is `f % 2`;
//!   [`FACE_CORNERS`] lists its corners in increasing order, so its diagonals are
//!   corners `0–3` and `1–2` of that list.
//! * **Case index.** Bit `i` of the case is set when the value at corner `i` is `< iso`
//!   ("below"). Values `>= iso` (and NaN, which never compares below) are "above".
//! * **Orientation.** Triangles are counter-clockwise (right-hand rule) when seen from the
//!   below side: their normal points from above-iso toward below-iso values, against the
//!   gradient. This is VTK's convention: for a scan thresholded at tissue, normals point
//!   out of the tissue and the enclosed volume is positive.
//! * **Ambiguous faces.** A face whose above corners are diagonal can be cut two ways:
//!   joining its two above corners across the face centre or separating them. Each case
//!   has one table row per combination of choices on its ambiguous faces
//!   ([`McTables::row`]); the choice is made per face from that face's four values only
//!   ([`crate::mc_ambiguity`]), so the two cells sharing a face cut it identically and
//!   the extracted surface is watertight.

use std::sync::OnceLock;

use glam::IVec3;

/// Offset of each cell corner from the cell's minimum corner (bit 0 = x, 1 = y, 2 = z).
#[rustfmt::skip]
pub const CORNER_OFFSETS: [[u8; 3]; 8] = [
    [0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0],
    [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1],
];

/// `[start, end]` corners of each edge; the start has the smaller coordinate.
#[rustfmt::skip]
pub const EDGE_CORNERS: [[u8; 2]; 12] = [
    [0, 1], [2, 3], [4, 5], [6, 7], // along x
    [0, 2], [1, 3], [4, 6], [5, 7], // along y
    [0, 4], [1, 5], [2, 6], [3, 7], // along z
];

/// Axis (0 = x, 1 = y, 2 = z) each edge runs along.
pub const EDGE_AXIS: [u8; 12] = [0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2];

/// Corners of each face in increasing order (see the module docs): entries 0 and 3 are one
/// diagonal, 1 and 2 the other.
#[rustfmt::skip]
pub const FACE_CORNERS: [[u8; 4]; 6] = [
    [0, 2, 4, 6], [1, 3, 5, 7], // x = 0, x = 1
    [0, 1, 4, 5], [2, 3, 6, 7], // y = 0, y = 1
    [0, 1, 2, 3], [4, 5, 6, 7], // z = 0, z = 1
];

/// Most triangles any row holds. A cell's surface is a set of closed loops through its
/// crossing edges, each fanned into (length - 2) triangles; with every face ambiguous and
/// cut so that all 12 crossings form one loop, that is 10.
pub const MAX_TRIANGLES: usize = 10;

/// The tables (see the module docs for the conventions). Per case: which edges cross and
/// which faces are ambiguous; per row (a case with one choice on each of its ambiguous
/// faces): the triangles.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McTables {
    /// Bit `e` set when edge `e` crosses the isosurface in this case.
    pub edge_mask: [u16; 256],
    /// Bit `f` set when face `f` is ambiguous in this case (its four edges cross).
    pub ambiguous_faces: [u8; 256],
    /// Index of the case's first row; it has `2^(ambiguous faces)` rows (see [`Self::row`]).
    pub first_row: [u16; 256],
    /// Number of triangles in each row (0..=[`MAX_TRIANGLES`]).
    pub tri_count: Vec<u8>,
    /// Triangle corners of each row as edge ids, three per triangle, padded with `-1`.
    pub tris: Vec<[i8; 3 * MAX_TRIANGLES]>,
}

impl McTables {
    /// The row of `case` whose ambiguous faces are cut as `joined` says: bit `f` set joins
    /// the above corners of face `f`. Bits of faces that are not ambiguous are ignored.
    /// Rows of a case follow its ambiguous faces in increasing order, the lowest face
    /// being bit 0 of the offset from [`Self::first_row`].
    pub fn row(&self, case: u8, joined: u8) -> usize {
        let c = usize::from(case);
        usize::from(self.first_row[c]) + compact_bits(joined, self.ambiguous_faces[c])
    }

    pub fn row_count(&self) -> usize {
        self.tri_count.len()
    }

    /// The triangles of `row` as edge-id triples.
    pub fn row_triangles(&self, row: usize) -> impl Iterator<Item = [usize; 3]> + '_ {
        let n = usize::from(self.tri_count[row]);
        self.tris[row][..3 * n]
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]].map(|e| e as usize))
    }
}

/// The bits of `value` selected by `mask`, packed toward bit 0 in order.
fn compact_bits(value: u8, mask: u8) -> usize {
    (0..6)
        .filter(|&f| mask >> f & 1 == 1)
        .enumerate()
        .fold(0, |out, (k, f)| out | usize::from(value >> f & 1) << k)
}

/// The inverse of [`compact_bits`]: spreads bit `k` of `packed` onto the `k`-th set bit
/// of `mask`.
fn spread_bits(packed: usize, mask: u8) -> u8 {
    (0..6)
        .filter(|&f| mask >> f & 1 == 1)
        .enumerate()
        .fold(0, |out, (k, f)| out | ((packed >> k & 1) as u8) << f)
}

/// The tables, generated on first call and shared afterwards.
pub fn mc_tables() -> &'static McTables {
    static TABLES: OnceLock<McTables> = OnceLock::new();
    TABLES.get_or_init(generate)
}

/// Whether `corner` is below iso in `case`.
pub fn corner_below(case: u8, corner: usize) -> bool {
    (case >> corner) & 1 == 1
}

/// Whether edge `e` crosses the isosurface in `case` (its corners disagree).
pub fn edge_crosses(case: u8, e: usize) -> bool {
    let [a, b] = EDGE_CORNERS[e];
    corner_below(case, a as usize) != corner_below(case, b as usize)
}

/// Corner position scaled by 2, so edge midpoints and face centres stay integral.
fn corner2(c: usize) -> IVec3 {
    IVec3::from_array(CORNER_OFFSETS[c].map(i32::from)) * 2
}

/// Edge midpoint scaled by 2.
pub(crate) fn edge_mid2(e: usize) -> IVec3 {
    let [a, b] = EDGE_CORNERS[e];
    (corner2(a as usize) + corner2(b as usize)) / 2
}

/// Face `f` is the cell face with coordinate `f / 2` equal to `f % 2`; returns the
/// outward normal.
pub(crate) fn face_normal(f: usize) -> IVec3 {
    IVec3::AXES[f / 2] * if f % 2 == 1 { 1 } else { -1 }
}

pub(crate) fn corner_on_face(c: usize, f: usize) -> bool {
    usize::from(CORNER_OFFSETS[c][f / 2]) == f % 2
}

pub(crate) fn edge_on_face(e: usize, f: usize) -> bool {
    let [a, b] = EDGE_CORNERS[e];
    corner_on_face(a as usize, f) && corner_on_face(b as usize, f)
}

/// The edges of face `f` that cross the isosurface in `case` (0, 2 or 4 of them).
pub(crate) fn face_crossings(case: u8, f: usize) -> Vec<usize> {
    (0..12)
        .filter(|&e| edge_on_face(e, f) && edge_crosses(case, e))
        .collect()
}

fn edges_share_face(a: usize, b: usize) -> bool {
    (0..6).any(|f| edge_on_face(a, f) && edge_on_face(b, f))
}

/// The directed iso-segments of `case` on every face, as `(from_edge, to_edge)`, with the
/// ambiguous faces cut as `joined` says (see [`McTables::row`]).
///
/// Each segment is directed so that, walking it, the above side of the face is on the
/// right when looking at the face from outside the cell. Chained into loops this makes
/// every loop counter-clockwise seen from the below side, which is the orientation the
/// triangles need (see the module docs).
pub(crate) fn face_segments(case: u8, joined: u8) -> Vec<(usize, usize)> {
    let mut segs = Vec::new();
    for f in 0..6 {
        let corners: Vec<usize> = (0..8).filter(|&c| corner_on_face(c, f)).collect();
        let crossing = face_crossings(case, f);
        let centre = corners.iter().map(|&c| corner2(c)).sum::<IVec3>() / 4;
        // `(edge, edge, g)` where g points, within the face, from below toward above.
        let mut pairs: Vec<(usize, usize, IVec3)> = Vec::new();
        match crossing.len() {
            0 => {}
            2 => {
                // One straight cut: g is the signed sum of the corners around the centre,
                // a multiple of (above centroid - below centroid).
                let sign = |c: usize| if corner_below(case, c) { -1 } else { 1 };
                let g = corners
                    .iter()
                    .map(|&c| (corner2(c) - centre) * sign(c))
                    .sum();
                pairs.push((crossing[0], crossing[1], g));
            }
            4 => {
                // Ambiguous face: the centre belongs to the above side when the above
                // corners are joined, so each below corner is cut off on its own;
                // otherwise each above corner is.
                let join_above = joined >> f & 1 == 1;
                for &c in corners
                    .iter()
                    .filter(|&&c| corner_below(case, c) == join_above)
                {
                    let around: Vec<usize> = crossing
                        .iter()
                        .copied()
                        .filter(|&e| EDGE_CORNERS[e].contains(&(c as u8)))
                        .collect();
                    let toward_centre = centre - corner2(c);
                    let g = if join_above {
                        toward_centre
                    } else {
                        -toward_centre
                    };
                    pairs.push((around[0], around[1], g));
                }
            }
            n => unreachable!("a face has an even number of crossings, got {n}"),
        }
        for (a, b, g) in pairs {
            // With n the outward face normal, the direction n x g has the above side on
            // its right seen from outside (derivation: the surface's in-plane normal
            // follows -g, and the above part must lie inside the cell).
            let along = (edge_mid2(b) - edge_mid2(a)).dot(face_normal(f).cross(g));
            debug_assert_ne!(along, 0);
            segs.push(if along > 0 { (a, b) } else { (b, a) });
        }
    }
    segs
}

/// Chains the directed face segments of `case` (ambiguous faces cut as `joined` says)
/// into closed loops of edge ids.
pub(crate) fn loops(case: u8, joined: u8) -> Vec<Vec<usize>> {
    let mut next = [usize::MAX; 12];
    for (a, b) in face_segments(case, joined) {
        assert_eq!(next[a], usize::MAX, "case {case}: edge {a} leaves twice");
        next[a] = b;
    }
    let mut seen = [false; 12];
    let mut out = Vec::new();
    for start in 0..12 {
        if seen[start] || !edge_crosses(case, start) {
            continue;
        }
        let mut lp = Vec::new();
        let mut e = start;
        while !seen[e] {
            assert_ne!(next[e], usize::MAX, "case {case}: loop open at edge {e}");
            seen[e] = true;
            lp.push(e);
            e = next[e];
        }
        assert_eq!(e, start, "case {case}: segments do not close into a loop");
        out.push(lp);
    }
    out
}

/// Triangulates a loop, keeping its winding, avoiding diagonals that join two edges of one
/// cell face: such a diagonal lies in the face and could coincide with the neighbouring
/// cell's, making a mesh edge shared by four triangles.
///
/// A fan is taken where one works (every loop of the classic cases has one). Some loops
/// that only arise with mixed choices on ambiguous faces (eight or more crossings winding
/// around the cell, 116 of the 656 rows) have no triangulation free of face diagonals;
/// they get one with the fewest, each of a kind the neighbour across that face never uses
/// ([`face_diagonal_allowed`]), so the surface stays a closed manifold.
fn triangulate(lp: &[usize]) -> Vec<[usize; 3]> {
    let n = lp.len();
    let fan_apex = (0..n).find(|&s| (2..n - 1).all(|k| !edges_share_face(lp[s], lp[(s + k) % n])));
    if let Some(apex) = fan_apex {
        return (1..n - 1)
            .map(|k| [lp[apex], lp[(apex + k) % n], lp[(apex + k + 1) % n]])
            .collect();
    }
    let best = fewest_face_diagonals(lp);
    let mut tris = Vec::new();
    emit_triangulation(lp, &best, 0, n - 1, &mut tris);
    tris
}

/// Cost of a diagonal lying in a cell face that [`face_diagonal_allowed`] forbids: more than
/// all allowed diagonals of any triangulation together, so the search prefers any
/// triangulation without one (and generation asserts it always finds one).
const FORBIDDEN: u32 = 1000;

/// Whether a triangulation diagonal may join edges `a` and `b` of one face. Such a diagonal
/// can only cross an ambiguous face, from one of its segments to the other; the neighbour
/// across the face sees the same four crossings. A cell's lower faces (x, y or z = 0) take
/// only diagonals between parallel edges, its upper faces only between perpendicular ones,
/// and a lower face of one cell is an upper face of its neighbour, so the two never put a
/// diagonal on the same pair: no mesh edge is shared by more than two triangles.
fn face_diagonal_allowed(a: usize, b: usize) -> bool {
    let parallel = EDGE_AXIS[a] == EDGE_AXIS[b];
    (0..6)
        .filter(|&f| edge_on_face(a, f) && edge_on_face(b, f))
        .all(|f| parallel == (f % 2 == 0))
}

/// For the polygon `lp`: `best[i][j] = (cost, apex)`, the fewest diagonals lying in a face
/// (each allowed one costs 1, a forbidden one [`FORBIDDEN`]) over the triangulations of the
/// sub-polygon `i..=j` (side `i–j` not counted), and the apex of the triangle on side `i–j`
/// that achieves it (the lowest such apex).
fn fewest_face_diagonals(lp: &[usize]) -> Vec<Vec<(u32, usize)>> {
    let n = lp.len();
    let cost = |i: usize, j: usize| {
        let (a, b) = (lp[i], lp[j]);
        match (
            j - i > 1 && edges_share_face(a, b),
            face_diagonal_allowed(a, b),
        ) {
            (false, _) => 0,
            (true, true) => 1,
            (true, false) => FORBIDDEN,
        }
    };
    let mut best = vec![vec![(0u32, 0usize); n]; n];
    for span in 2..n {
        for i in 0..n - span {
            let j = i + span;
            best[i][j] = (i + 1..j)
                .map(|k| (best[i][k].0 + best[k][j].0 + cost(i, k) + cost(k, j), k))
                .min()
                .expect("a span of two or more has an apex");
        }
    }
    assert!(
        best[0][n - 1].0 < FORBIDDEN,
        "loop {lp:?} needs a face diagonal its neighbour might share"
    );
    best
}

fn emit_triangulation(
    lp: &[usize],
    best: &[Vec<(u32, usize)>],
    i: usize,
    j: usize,
    tris: &mut Vec<[usize; 3]>,
) {
    if j - i < 2 {
        return;
    }
    let k = best[i][j].1;
    tris.push([lp[j], lp[i], lp[k]]);
    emit_triangulation(lp, best, i, k, tris);
    emit_triangulation(lp, best, k, j, tris);
}

fn generate() -> McTables {
    let mut t = McTables {
        edge_mask: [0; 256],
        ambiguous_faces: [0; 256],
        first_row: [0; 256],
        tri_count: Vec::new(),
        tris: Vec::new(),
    };
    for case in 0..=255u8 {
        let c = usize::from(case);
        t.edge_mask[c] = (0..12)
            .filter(|&e| edge_crosses(case, e))
            .fold(0, |m, e| m | 1 << e);
        let ambiguous = (0..6)
            .filter(|&f| face_crossings(case, f).len() == 4)
            .fold(0u8, |m, f| m | 1 << f);
        t.ambiguous_faces[c] = ambiguous;
        t.first_row[c] = u16::try_from(t.tri_count.len()).expect("row index fits 16 bits");
        for choice in 0..1usize << ambiguous.count_ones() {
            let joined = spread_bits(choice, ambiguous);
            let tris: Vec<[usize; 3]> = loops(case, joined)
                .iter()
                .flat_map(|l| triangulate(l))
                .collect();
            assert!(
                tris.len() <= MAX_TRIANGLES,
                "case {case} (joined {joined:#b}) needs {} triangles",
                tris.len()
            );
            let mut row = [-1i8; 3 * MAX_TRIANGLES];
            for (slot, &e) in row.iter_mut().zip(tris.iter().flatten()) {
                *slot = e as i8;
            }
            t.tri_count.push(tris.len() as u8);
            t.tris.push(row);
        }
    }
    t
}

#[cfg(test)]
#[path = "mc_tables_tests.rs"]
mod tests;
