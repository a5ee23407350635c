use super::format::{MAX_OCCUPIED_CELLS, MAX_TRIANGLES, MAX_VERTICES};
use super::partition::partition_block;
use super::subblock::{Subblock, SubblockSurface};
use crate::marching_cubes::AmbiguityRule;
use crate::mc_tables::mc_tables;
use crate::test_volumes::field;

const RULES: [AmbiguityRule; 2] = [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk];

/// 0 and 1 alternating along every axis: every edge crosses 0.5, so every cell holds surface.
fn checkerboard(dims: [u32; 3]) -> crate::Volume {
    field(dims, |p| ((p.x + p.y + p.z) as u32 % 2) as f32)
}

#[test]
fn the_smallest_subblock_always_fits_one_meshlet() {
    // 2×2×2 cells: 3×3 lines of 2 edges along each axis, 8 cells, and the tables' largest row.
    let edges = 3 * (2 * 3 * 3);
    let cells = 8;
    let most_triangles = u32::from(*mc_tables().tri_count.iter().max().unwrap());
    assert!(edges <= MAX_VERTICES, "{edges} vertices");
    assert!(cells <= MAX_OCCUPIED_CELLS);
    assert!(
        cells * most_triangles <= MAX_TRIANGLES,
        "{cells} cells × {most_triangles} triangles"
    );
}

#[test]
fn subblocks_tile_the_block_level_by_level() {
    let block = Subblock::whole_block([8, 16, 4]);
    assert_eq!((block.origin(), block.size()), ([8, 16, 4], [8, 8, 4]));
    let quarters: Vec<_> = block.parts().collect();
    let origins: Vec<_> = quarters.iter().map(|q| q.origin()).collect();
    assert_eq!(origins, [[8, 16, 4], [12, 16, 4], [8, 20, 4], [12, 20, 4]]);
    assert!(quarters.iter().all(|q| q.size() == [4; 3]));
    let eighths: Vec<_> = quarters[3].parts().collect();
    assert_eq!(eighths.len(), 8);
    assert_eq!(eighths[7].origin(), [14, 22, 6]);
    assert!(eighths.iter().all(|e| e.size() == [2; 3]));
    assert_eq!(eighths[0].parts().count(), 0);
}

#[test]
fn a_fully_occupied_block_splits_into_full_eighths() {
    // One block exactly (9×9×5 samples). Its quarters' boxes have 300 crossed edges each, far
    // over the vertex limit, so all 32 eighths are extracted, each with all 54 of its edges.
    let volume = checkerboard([9, 9, 5]);
    for rule in RULES {
        let parts = partition_block(&volume, 0.5, rule, [0; 3]).unwrap();
        assert_eq!(parts.len(), 32, "{rule:?}");
        for part in &parts {
            assert_eq!(part.subblock.size(), [2; 3]);
            assert_eq!(part.vertex_count(), 54);
            assert_eq!(part.occupied_cell_count(), 8);
            assert!(part.fits());
        }
        let quarter = SubblockSurface::scan(&volume, 0.5, rule, parts[0].subblock);
        assert_eq!(quarter.vertex_count(), 54);
        let first_quarter = Subblock::whole_block([0; 3]).parts().next().unwrap();
        let quarter = SubblockSurface::scan(&volume, 0.5, rule, first_quarter);
        assert_eq!(quarter.vertex_count(), 3 * 4 * 5 * 5);
        assert_eq!(quarter.occupied_cell_count(), 64);
    }
}

#[test]
fn a_plane_through_a_block_is_one_meshlet() {
    // z = 1.5 crosses all 64 cells of one layer: 81 vertices and 128 triangles fit.
    let volume = field([9, 9, 5], |p| p.z);
    let parts = partition_block(&volume, 1.5, AmbiguityRule::default(), [0; 3]).unwrap();
    assert_eq!(parts.len(), 1);
    let whole = &parts[0];
    assert_eq!(whole.subblock.size(), [8, 8, 4]);
    assert_eq!(whole.occupied_cell_count(), 64);
    assert_eq!(whole.vertex_count(), 81);
    assert_eq!(whole.triangle_count, 128);
}

#[test]
fn a_quarter_too_full_for_one_meshlet_is_cut_but_its_neighbours_are_not() {
    // A plane through the whole block (one layer of 64 cells, 81 vertices, 128 triangles)
    // plus a checkerboard corner in the quarter at x, y >= 4: the block and that quarter
    // overflow, the other quarters keep one meshlet each.
    let volume = field([9, 9, 5], |p| {
        if p.x >= 4.0 && p.y >= 4.0 && p.z >= 2.0 {
            ((p.x + p.y + p.z) as u32 % 2) as f32
        } else {
            f32::from(p.z >= 2.0)
        }
    });
    let parts = partition_block(&volume, 0.5, AmbiguityRule::Vtk, [0; 3]).unwrap();
    let sizes: Vec<_> = parts.iter().map(|p| p.subblock.size()[0]).collect();
    assert_eq!(&sizes[..3], [4, 4, 4]);
    assert!(sizes[3..].iter().all(|&s| s == 2), "{sizes:?}");
    assert!(parts.iter().all(|p| p.fits()));
}

#[test]
fn too_many_occupied_cells_alone_split_a_block() {
    // Isolated low samples at 21 of the block's 32 interior points of odd coordinates: each
    // closes a small octahedron of 6 vertices and 8 single-triangle cells, so the block needs
    // 126 vertices and 168 triangles (both within the limits) but has 168 occupied cells.
    let low: Vec<[u32; 3]> = (0..32)
        .map(|k| [1 + 2 * (k % 4), 1 + 2 * (k / 4 % 4), 1 + 2 * (k / 16)])
        .take(21)
        .collect();
    let volume = field([9, 9, 5], |p| {
        let p = p.to_array().map(|c| c as u32);
        if low.contains(&p) {
            0.0
        } else {
            1.0
        }
    });
    let whole = SubblockSurface::scan(
        &volume,
        0.5,
        AmbiguityRule::default(),
        Subblock::whole_block([0; 3]),
    );
    assert_eq!(whole.vertex_count(), 126);
    assert_eq!(whole.triangle_count, 168);
    assert_eq!(whole.occupied_cell_count(), 168);
    assert!(!whole.fits());
    let parts = partition_block(&volume, 0.5, AmbiguityRule::default(), [0; 3]).unwrap();
    assert!(parts.len() > 1);
    assert!(parts
        .iter()
        .all(|p| p.occupied_cell_count() <= MAX_OCCUPIED_CELLS));
}
