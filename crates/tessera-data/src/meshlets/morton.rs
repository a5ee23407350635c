//! Morton order of the cells of an 8×8×4 block. Bits of the code, lowest first, are
//! `x0 y0 z0 x1 y1 z1 x2 y2`, so every aligned run of 8 codes is a 2×2×2 subblock (what one
//! invocation of the region analysis walks) and every aligned run of 64 a 4×4×4 subblock:
//! each candidate subblock is a range of consecutive codes, summed by consecutive
//! invocations.

use crate::minmax::BLOCK_CELLS;

/// Cells in one block.
pub const BLOCK_CELL_COUNT: u32 = BLOCK_CELLS[0] * BLOCK_CELLS[1] * BLOCK_CELLS[2];

/// Position of the cell with Morton `code` (`< BLOCK_CELL_COUNT`) inside its block.
pub fn cell_of_code(code: u32) -> [u32; 3] {
    let bit = |b: u32| (code >> b) & 1;
    [
        bit(0) | bit(3) << 1 | bit(6) << 2,
        bit(1) | bit(4) << 1 | bit(7) << 2,
        bit(2) | bit(5) << 1,
    ]
}

/// Morton code of the cell at `cell` inside its block (each coordinate below
/// [`BLOCK_CELLS`]).
pub fn code_of_cell(cell: [u32; 3]) -> u32 {
    let [x, y, z] = cell;
    let bit = |v: u32, b: u32| (v >> b) & 1;
    bit(x, 0)
        | bit(y, 0) << 1
        | bit(z, 0) << 2
        | bit(x, 1) << 3
        | bit(y, 1) << 4
        | bit(z, 1) << 5
        | bit(x, 2) << 6
        | bit(y, 2) << 7
}
