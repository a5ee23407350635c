//! Turning VTK cell lists (legacy and XML files share them) into tets.

use crate::error::{DataError, Result};

/// VTK cell types the loaders turn into tets.
pub const VTK_TETRA: u8 = 10;
pub const VTK_QUADRATIC_TETRA: u8 = 24;

/// Tets gathered from a VTK cell list.
pub(crate) struct Cells {
    pub tets: Vec<[u32; 4]>,
    /// Index of the source cell of every tet (to pick cell data).
    pub kept: Vec<usize>,
    pub skipped: usize,
}

/// Turns a VTK cell list (`starts` has one entry per cell plus the end) into tets,
/// checking point indices. `err(cell, message)` places an error.
pub(crate) fn collect_tets(
    connectivity: &[f64],
    starts: &[usize],
    types: &[f64],
    npoints: usize,
    err: impl Fn(usize, String) -> DataError,
) -> Result<Cells> {
    let mut cells = Cells {
        tets: Vec::new(),
        kept: Vec::new(),
        skipped: 0,
    };
    for (c, &kind) in types.iter().enumerate() {
        let ids = &connectivity[starts[c]..starts[c + 1]];
        let want = match kind as i64 {
            k if k == i64::from(VTK_TETRA) => 4,
            k if k == i64::from(VTK_QUADRATIC_TETRA) => 10,
            _ => {
                cells.skipped += 1;
                continue;
            }
        };
        if ids.len() != want {
            return Err(err(
                c,
                format!(
                    "cell {c} of type {kind} has {} points, expected {want}",
                    ids.len()
                ),
            ));
        }
        let mut tet = [0u32; 4];
        for (slot, &id) in tet.iter_mut().zip(ids) {
            if !(id >= 0.0 && id < npoints as f64) {
                return Err(err(
                    c,
                    format!(
                        "cell {c}: point index {id} out of range (the mesh has {npoints} points)"
                    ),
                ));
            }
            *slot = id as u32;
        }
        cells.kept.push(c);
        cells.tets.push(tet);
    }
    Ok(cells)
}
