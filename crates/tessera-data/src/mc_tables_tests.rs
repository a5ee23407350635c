use super::*;
use std::collections::HashMap;

/// Every `(case, joined, row)` of the tables, `joined` holding only ambiguous faces.
fn all_rows() -> Vec<(u8, u8, usize)> {
    let t = mc_tables();
    (0..=255u8)
        .flat_map(|case| {
            let amb = t.ambiguous_faces[usize::from(case)];
            (0..1usize << amb.count_ones()).map(move |k| {
                let joined = spread_bits(k, amb);
                (case, joined, t.row(case, joined))
            })
        })
        .collect()
}

fn row_tris(row: usize) -> Vec<[usize; 3]> {
    let t = mc_tables();
    let n = usize::from(t.tri_count[row]);
    assert!(t.tris[row][3 * n..].iter().all(|&e| e == -1));
    t.row_triangles(row).collect()
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
    for (f, corners) in FACE_CORNERS.iter().enumerate() {
        let on: Vec<u8> = (0..8u8).filter(|&c| corner_on_face(c.into(), f)).collect();
        assert_eq!(corners.to_vec(), on, "face {f}");
    }
}

#[test]
fn rows_are_laid_out_by_case_and_ambiguous_face() {
    let t = mc_tables();
    let rows = all_rows();
    assert_eq!(rows.len(), t.row_count());
    for (i, &(_, _, row)) in rows.iter().enumerate() {
        assert_eq!(row, i, "rows follow case, then the compacted face bits");
    }
    // Bits of unambiguous faces do not move the row.
    for &(case, joined, row) in &rows {
        assert_eq!(
            t.row(case, joined | !t.ambiguous_faces[usize::from(case)]),
            row
        );
    }
    let per_count = |n: u32| {
        (0..256)
            .filter(|&c| t.ambiguous_faces[c].count_ones() == n)
            .count()
    };
    println!(
        "marching-cubes tables: {} rows; cases by ambiguous faces: {:?}",
        t.row_count(),
        (0..=6).map(per_count).collect::<Vec<_>>()
    );
    assert_eq!(
        t.row_count(),
        (0..256)
            .map(|c| 1usize << t.ambiguous_faces[c].count_ones())
            .sum::<usize>()
    );
    assert_eq!(per_count(6), 2, "the two checkerboards");
}

#[test]
fn trivial_cases_are_empty_and_counts_bounded() {
    let t = mc_tables();
    for c in [0u8, 255] {
        assert_eq!(t.edge_mask[usize::from(c)], 0);
        assert_eq!(t.tri_count[t.row(c, 0)], 0);
    }
    for (case, _, row) in all_rows() {
        let vertices = t.edge_mask[usize::from(case)].count_ones();
        let tris = u32::from(t.tri_count[row]);
        assert!(usize::from(t.tri_count[row]) <= MAX_TRIANGLES);
        // The mesh-workgroup limits rely on a cell's triangles being at most its
        // vertices minus two (one loop of n crossings gives n - 2 triangles).
        assert!(
            tris == 0 && vertices == 0 || tris + 2 <= vertices,
            "case {case}"
        );
    }
    assert_eq!(
        t.tri_count.iter().map(|&n| usize::from(n)).max(),
        Some(MAX_TRIANGLES),
        "MAX_TRIANGLES is reached, so it is not larger than needed"
    );
    // With the above corners always joined the tables are the classic 256 rows.
    let joined_all: u32 = (0..=255u8)
        .map(|c| u32::from(t.tri_count[t.row(c, 0x3f)]))
        .sum();
    assert_eq!(joined_all, 820);
}

#[test]
fn triangles_use_exactly_the_crossing_edges() {
    for (case, joined, row) in all_rows() {
        let used = row_tris(row)
            .iter()
            .flatten()
            .fold(0u16, |m, &e| m | 1 << e);
        assert_eq!(
            used,
            mc_tables().edge_mask[usize::from(case)],
            "case {case} joined {joined:#b}"
        );
    }
}

#[test]
fn triangle_boundary_is_exactly_the_face_segments() {
    let mut rows_with_face_diagonals = 0;
    for (case, joined, row) in all_rows() {
        // Directed edge -> uses. Inner fan diagonals must appear once each way, the
        // boundary must be the directed face segments, each exactly once.
        let mut directed: HashMap<(usize, usize), u32> = HashMap::new();
        for [a, b, c] in row_tris(row) {
            for e in [(a, b), (b, c), (c, a)] {
                *directed.entry(e).or_default() += 1;
            }
        }
        assert!(
            directed.values().all(|&n| n == 1),
            "case {case} joined {joined:#b}: repeated edge"
        );
        let mut boundary: Vec<(usize, usize)> = directed
            .keys()
            .copied()
            .filter(|&(a, b)| !directed.contains_key(&(b, a)))
            .collect();
        let mut segs = face_segments(case, joined);
        segs.sort_unstable();
        boundary.sort_unstable();
        assert_eq!(boundary, segs, "case {case} joined {joined:#b}");
        let face_diagonals: Vec<(usize, usize)> = directed
            .keys()
            .copied()
            .filter(|&(a, b)| a < b && directed.contains_key(&(b, a)) && edges_share_face(a, b))
            .collect();
        for &(a, b) in &face_diagonals {
            assert!(
                face_diagonal_allowed(a, b),
                "case {case} joined {joined:#b}: {a}-{b}"
            );
        }
        let face_diagonals = face_diagonals.len();
        if face_diagonals > 0 {
            // Only long loops winding around the cell need one (see `triangulate`).
            let longest = loops(case, joined).iter().map(Vec::len).max().unwrap_or(0);
            assert!(longest >= 8, "case {case} joined {joined:#b}");
            rows_with_face_diagonals += 1;
        }
        // The rules' own rows (all joined, all separated) have none.
        let amb = mc_tables().ambiguous_faces[usize::from(case)];
        if joined == 0 || joined == amb {
            assert_eq!(face_diagonals, 0, "case {case} joined {joined:#b}");
        }
    }
    println!("rows with a diagonal in a face: {rows_with_face_diagonals}");
    assert_eq!(rows_with_face_diagonals, 116);
}

#[test]
fn triangles_face_from_above_to_below() {
    // The above part of the cell is closed by the triangles plus the above parts of the
    // six faces, so its outward area vectors must cancel: the triangles' normals point out
    // of it, toward the below side. Flipped triangles would leave twice the face term.
    // Everything is scaled by 8 to stay integral.
    for (case, joined, row) in all_rows() {
        let mut sum: IVec3 = row_tris(row)
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(edge_mid2);
                (b - a).cross(c - a)
            })
            .sum();
        for f in 0..6 {
            let above = (0..8)
                .filter(|&c| corner_on_face(c, f) && !corner_below(case, c))
                .count();
            // Above area of a unit face cut at edge midpoints, times 8: a corner 1/8, half
            // a face 1/2, three corners 7/8; an ambiguous face's two above corners 2/8 when
            // separated, 6/8 when joined (all but the two below corners).
            let area8 = match (above, face_crossings(case, f).len()) {
                (2, 4) if joined >> f & 1 == 1 => 6,
                (2, 4) => 2,
                (n, _) => [0, 1, 4, 7, 8][n],
            };
            sum += face_normal(f) * area8;
        }
        assert_eq!(sum, IVec3::ZERO, "case {case} joined {joined:#b}");
    }
}

#[test]
fn complementary_cases_are_the_same_surface_reversed() {
    // Swapping above and below turns "joined above" into "separated above" on every
    // ambiguous face; the surface is the same with every segment reversed.
    let t = mc_tables();
    for (case, joined, row) in all_rows() {
        let amb = t.ambiguous_faces[usize::from(case)];
        assert_eq!(t.ambiguous_faces[usize::from(255 - case)], amb);
        assert_eq!(
            t.edge_mask[usize::from(case)],
            t.edge_mask[usize::from(255 - case)]
        );
        let other = t.row(255 - case, !joined & amb);
        assert_eq!(
            t.tri_count[row], t.tri_count[other],
            "case {case} joined {joined:#b}"
        );
        let mut mine: Vec<(usize, usize)> = face_segments(case, joined)
            .into_iter()
            .map(|(a, b)| (b, a))
            .collect();
        let mut theirs = face_segments(255 - case, !joined & amb);
        mine.sort_unstable();
        theirs.sort_unstable();
        assert_eq!(mine, theirs, "case {case} joined {joined:#b}");
    }
}

#[test]
fn neighbours_never_allow_the_same_face_diagonal() {
    // The cell across face 2a + 1 sees it as its face 2a, its edges shifted by one step
    // along axis a; whatever pair one side may join, the other may not.
    let shifted = |e: usize, axis: usize| -> usize {
        let [a, b] = EDGE_CORNERS[e].map(|c| c | 1 << axis);
        (0..12).find(|&s| EDGE_CORNERS[s] == [a, b]).unwrap()
    };
    let mut pairs = 0;
    for axis in 0..3 {
        let lower: Vec<usize> = (0..12).filter(|&e| edge_on_face(e, 2 * axis)).collect();
        for (i, &a) in lower.iter().enumerate() {
            for &b in &lower[i + 1..] {
                let (a2, b2) = (shifted(a, axis), shifted(b, axis));
                assert!(edge_on_face(a2, 2 * axis + 1) && edge_on_face(b2, 2 * axis + 1));
                assert_ne!(face_diagonal_allowed(a, b), face_diagonal_allowed(a2, b2));
                pairs += 1;
            }
        }
    }
    assert_eq!(pairs, 3 * 6);
}

#[test]
fn compact_and_spread_are_inverse() {
    for mask in 0..64u8 {
        for k in 0..1usize << mask.count_ones() {
            assert_eq!(compact_bits(spread_bits(k, mask), mask), k);
        }
    }
    assert_eq!(compact_bits(0b10_0100, 0b11_0100), 0b101);
}
