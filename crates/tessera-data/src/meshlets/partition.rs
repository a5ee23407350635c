//! Region analysis (paper C §3.2.1): the partition of one occupied 8×8×4 block into the
//! subblocks whose surfaces each fit one meshlet. The whole block is tried first; when it
//! does not fit, each 4×4×4 quarter is tried, and each quarter that does not fit is cut into
//! its 2×2×2 eighths. Subblocks without surface are dropped.
//!
//! A 2×2×2 subblock always fits: its closed box has 54 edges (at most 54 vertices ≤ 128), it
//! has 8 cells (≤ 128 occupied) and at most 8 × [`crate::mc_tables::MAX_TRIANGLES`] = 80
//! triangles (≤ 254); `partition_tests.rs` checks these bounds against the tables. (The
//! paper says 40 triangles: classic tables have at most 5 per cell, ours up to 10 where
//! the asymptotic decider joins several ambiguous faces of one cell.)

use crate::error::{DataError, Result};
use crate::marching_cubes::AmbiguityRule;
use crate::meshlets::subblock::{Subblock, SubblockSurface};
use crate::volume::Volume;

/// The non-empty subblocks of the block whose minimum cell is `block_origin`, in Morton
/// order, each with the surface its meshlet holds.
pub fn partition_block(
    volume: &Volume,
    iso: f32,
    rule: AmbiguityRule,
    block_origin: [u32; 3],
) -> Result<Vec<SubblockSurface>> {
    let mut out = Vec::new();
    place(
        volume,
        iso,
        rule,
        Subblock::whole_block(block_origin),
        &mut out,
    )?;
    Ok(out)
}

fn place(
    volume: &Volume,
    iso: f32,
    rule: AmbiguityRule,
    subblock: Subblock,
    out: &mut Vec<SubblockSurface>,
) -> Result<()> {
    let surface = SubblockSurface::scan(volume, iso, rule, subblock);
    if surface.is_empty() {
        return Ok(());
    }
    if surface.fits() {
        out.push(surface);
        return Ok(());
    }
    let mut parts = subblock.parts().peekable();
    if parts.peek().is_none() {
        // Unreachable by the bounds in the module docs; an error rather than an oversized
        // meshlet should the tables or limits ever change.
        return Err(DataError::Invalid(format!(
            "subblock at {:?} of size {:?} needs {} vertices, {} triangles and {} occupied \
             cells, more than one meshlet holds",
            subblock.origin(),
            subblock.size(),
            surface.vertex_count(),
            surface.triangle_count,
            surface.occupied_cell_count()
        )));
    }
    parts.try_for_each(|part| place(volume, iso, rule, part, out))
}
