//! Marching-cubes case tables, derived at first use from the cube's geometry instead of
//! being written out by hand, so every entry follows from the conventions below and the
//! tests can check the rules rather than 256 literal rows.
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
//! * **Case index.** Bit `i` of the case is set when the value at corner `i` is `< iso`
//!   ("below"/inside). Values `>= iso` (and NaN, which never compares below) are "above".
//! * **Orientation.** Triangles are counter-clockwise (right-hand rule) when seen from the
//!   above side: their normal points from below-iso toward above-iso values, i.e. along
//!   the gradient. For a distance field thresholded at a radius, normals point outward.
//! * **Ambiguous faces.** A face whose below corners are diagonal always keeps those two
//!   corners apart. The choice only looks at that face's corners, so the two cells sharing
//!   the face cut it identically and the extracted surface is watertight.

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

/// Most triangles any case produces; rows of [`McTables::tris`] hold this many.
pub const MAX_TRIANGLES: usize = 5;

/// Row stride of [`tri_table_flat`]: 15 edge ids plus one guaranteed `-1`, so a shader
/// can both index rows with a shift and stop at the first `-1`.
pub const TRI_TABLE_STRIDE: usize = 16;

/// The per-case tables, indexed by case (see the module docs for the conventions).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McTables {
    /// Bit `e` set when edge `e` crosses the isosurface in this case.
    pub edge_mask: [u16; 256],
    /// Number of triangles in this case (0..=5).
    pub tri_count: [u8; 256],
    /// Triangle corners as edge ids, three per triangle, padded with `-1`.
    pub tris: [[i8; 15]; 256],
}

/// The tables, generated on first call and shared afterwards.
pub fn mc_tables() -> &'static McTables {
    static TABLES: OnceLock<McTables> = OnceLock::new();
    TABLES.get_or_init(generate)
}

/// [`McTables::tris`] as `256 * TRI_TABLE_STRIDE` `i32`s, the layout GPU buffers want
/// (std430 arrays of `int` have no padding).
pub fn tri_table_flat() -> Vec<i32> {
    let t = mc_tables();
    let mut out = Vec::with_capacity(256 * TRI_TABLE_STRIDE);
    for row in &t.tris {
        out.extend(row.iter().map(|&e| i32::from(e)));
        out.push(-1);
    }
    out
}

/// [`McTables::edge_mask`] widened to `u32` for GPU upload.
pub fn edge_mask_flat() -> Vec<u32> {
    mc_tables()
        .edge_mask
        .iter()
        .map(|&m| u32::from(m))
        .collect()
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

/// The directed iso-segments of `case` on every face, as `(from_edge, to_edge)`.
///
/// Each segment is directed so that, walking it, the below side of the face is on the
/// right when looking at the face from outside the cell. Chained into loops this makes
/// every loop counter-clockwise seen from the above side, which is the orientation the
/// triangles need (see the module docs).
pub(crate) fn face_segments(case: u8) -> Vec<(usize, usize)> {
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
                // Ambiguous face: cut off each below corner on its own, so the two below
                // corners end up in separate regions (the fixed rule of the module docs).
                for &c in corners.iter().filter(|&&c| corner_below(case, c)) {
                    let around: Vec<usize> = crossing
                        .iter()
                        .copied()
                        .filter(|&e| EDGE_CORNERS[e].contains(&(c as u8)))
                        .collect();
                    pairs.push((around[0], around[1], centre - corner2(c)));
                }
            }
            n => unreachable!("a face has an even number of crossings, got {n}"),
        }
        for (a, b, g) in pairs {
            // With n the outward face normal, the direction g x n has the below side on
            // its right seen from outside (derivation: the surface's in-plane normal
            // follows g, and its interior must lie inside the cell).
            let along = (edge_mid2(b) - edge_mid2(a)).dot(g.cross(face_normal(f)));
            debug_assert_ne!(along, 0);
            segs.push(if along > 0 { (a, b) } else { (b, a) });
        }
    }
    segs
}

/// Chains the directed face segments of `case` into closed loops of edge ids.
pub(crate) fn loops(case: u8) -> Vec<Vec<usize>> {
    let mut next = [usize::MAX; 12];
    for (a, b) in face_segments(case) {
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

/// Fan-triangulates a loop, keeping its winding.
///
/// The fan apex is picked so no fan diagonal joins two edges of one cell face: such a
/// diagonal would lie in the face and could coincide with the neighbouring cell's
/// diagonal, making a mesh edge shared by four triangles.
fn fan(lp: &[usize]) -> Vec<[usize; 3]> {
    let n = lp.len();
    let apex = (0..n)
        .find(|&s| (2..n - 1).all(|k| !edges_share_face(lp[s], lp[(s + k) % n])))
        .unwrap_or(0);
    (1..n - 1)
        .map(|k| [lp[apex], lp[(apex + k) % n], lp[(apex + k + 1) % n]])
        .collect()
}

fn generate() -> McTables {
    let mut t = McTables {
        edge_mask: [0; 256],
        tri_count: [0; 256],
        tris: [[-1; 15]; 256],
    };
    for case in 0..=255u8 {
        let c = usize::from(case);
        t.edge_mask[c] = (0..12)
            .filter(|&e| edge_crosses(case, e))
            .fold(0, |m, e| m | 1 << e);
        let tris: Vec<[usize; 3]> = loops(case).iter().flat_map(|l| fan(l)).collect();
        assert!(
            tris.len() <= MAX_TRIANGLES,
            "case {case} needs {} triangles",
            tris.len()
        );
        t.tri_count[c] = tris.len() as u8;
        for (i, e) in tris.iter().flatten().enumerate() {
            t.tris[c][i] = *e as i8;
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn case_tris(case: usize) -> Vec<[usize; 3]> {
        let t = mc_tables();
        let n = usize::from(t.tri_count[case]);
        assert!(t.tris[case][3 * n..].iter().all(|&e| e == -1));
        t.tris[case][..3 * n]
            .chunks(3)
            .map(|c| [c[0], c[1], c[2]].map(|e| usize::try_from(e).unwrap()))
            .collect()
    }

    #[test]
    fn conventions_match_their_formulas() {
        for (i, o) in CORNER_OFFSETS.iter().enumerate() {
            assert_eq!(*o, [i & 1, (i >> 1) & 1, (i >> 2) & 1].map(|v| v as u8));
        }
        for e in 0..12 {
            let [a, b] = EDGE_CORNERS[e];
            assert_eq!(usize::from(EDGE_AXIS[e]), e / 4);
            assert_eq!(
                b - a,
                1 << EDGE_AXIS[e],
                "edge {e} runs along its axis from low to high"
            );
        }
    }

    #[test]
    fn trivial_cases_are_empty_and_counts_bounded() {
        let t = mc_tables();
        for c in [0, 255] {
            assert_eq!((t.tri_count[c], t.edge_mask[c]), (0, 0));
        }
        assert!(t.tri_count.iter().all(|&n| usize::from(n) <= MAX_TRIANGLES));
        let total: u32 = t.tri_count.iter().map(|&c| u32::from(c)).sum();
        println!("marching-cubes tables: {total} triangles over 256 cases");
        assert_eq!(total, 820);
    }

    #[test]
    fn triangles_use_exactly_the_crossing_edges() {
        for case in 0..256 {
            let used = case_tris(case)
                .iter()
                .flatten()
                .fold(0u16, |m, &e| m | 1 << e);
            assert_eq!(used, mc_tables().edge_mask[case], "case {case}");
        }
    }

    #[test]
    fn triangle_boundary_is_exactly_the_face_segments() {
        for case in 0..=255u8 {
            // Directed edge -> uses. Inner fan diagonals must appear once each way, the
            // boundary must be the directed face segments, each exactly once.
            let mut directed: HashMap<(usize, usize), u32> = HashMap::new();
            for [a, b, c] in case_tris(usize::from(case)) {
                for e in [(a, b), (b, c), (c, a)] {
                    *directed.entry(e).or_default() += 1;
                }
            }
            assert!(
                directed.values().all(|&n| n == 1),
                "case {case}: repeated edge"
            );
            let mut boundary: Vec<(usize, usize)> = directed
                .keys()
                .copied()
                .filter(|&(a, b)| !directed.contains_key(&(b, a)))
                .collect();
            let mut segs = face_segments(case);
            segs.sort_unstable();
            boundary.sort_unstable();
            assert_eq!(boundary, segs, "case {case}");
            for &(a, b) in directed.keys() {
                if directed.contains_key(&(b, a)) {
                    assert!(
                        !edges_share_face(a, b),
                        "case {case}: diagonal {a}-{b} in a face"
                    );
                }
            }
        }
    }

    #[test]
    fn triangles_face_from_below_to_above() {
        // The below part of the cell is closed by the triangles plus the below parts of
        // the six faces, so its outward area vectors must cancel. Flipped triangles would
        // leave twice the face term. Everything is scaled by 8 to stay integral.
        for case in 0..=255u8 {
            let mut sum: IVec3 = case_tris(usize::from(case))
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(edge_mid2);
                    (b - a).cross(c - a)
                })
                .sum();
            for f in 0..6 {
                let below = (0..8)
                    .filter(|&c| corner_on_face(c, f) && corner_below(case, c))
                    .count();
                let crossings = face_crossings(case, f).len();
                // Below area of a unit face, times 8: a corner cut off by midpoints is
                // 1/8, half a face 1/2, the two separated corners of an ambiguous face 1/4.
                let area8 = match (below, crossings) {
                    (2, 4) => 2,
                    (n, _) => [0, 1, 4, 7, 8][n],
                };
                sum += face_normal(f) * area8;
            }
            assert_eq!(sum, IVec3::ZERO, "case {case}");
        }
    }

    #[test]
    fn complementary_cases_match_without_ambiguity() {
        let t = mc_tables();
        for case in 0..=255u8 {
            let c = usize::from(case);
            assert_eq!(t.edge_mask[c], t.edge_mask[255 - c]);
            if (0..6).all(|f| face_crossings(case, f).len() < 4) {
                assert_eq!(t.tri_count[c], t.tri_count[255 - c], "case {case}");
            }
        }
    }

    #[test]
    fn flat_table_layout() {
        let flat = tri_table_flat();
        assert_eq!(flat.len(), 256 * TRI_TABLE_STRIDE);
        for (c, row) in flat.chunks(TRI_TABLE_STRIDE).enumerate() {
            let n = 3 * usize::from(mc_tables().tri_count[c]);
            assert!(row[..n].iter().all(|&e| (0..12).contains(&e)));
            assert!(row[n..].iter().all(|&e| e == -1));
        }
        assert_eq!(edge_mask_flat()[1], 1 | 1 << 4 | 1 << 8);
    }
}
