use super::morton::*;
use crate::minmax::BLOCK_CELLS;
use std::collections::HashSet;

#[test]
fn codes_cover_the_block_once_and_round_trip() {
    let cells: HashSet<[u32; 3]> = (0..BLOCK_CELL_COUNT).map(cell_of_code).collect();
    assert_eq!(cells.len(), 256);
    for code in 0..BLOCK_CELL_COUNT {
        let cell = cell_of_code(code);
        assert!((0..3).all(|a| cell[a] < BLOCK_CELLS[a]), "{cell:?}");
        assert_eq!(code_of_cell(cell), code);
    }
}

#[test]
fn aligned_runs_are_cubes() {
    for (run, side) in [(8, 2), (64, 4)] {
        for first in (0..BLOCK_CELL_COUNT).step_by(run) {
            let origin = cell_of_code(first);
            assert!(origin.iter().all(|c| c % side == 0), "{origin:?}");
            for code in first..first + run as u32 {
                let cell = cell_of_code(code);
                assert!(
                    (0..3).all(|a| cell[a] - origin[a] < side),
                    "code {code} at {cell:?} outside the {side}³ from {origin:?}"
                );
            }
        }
    }
}
