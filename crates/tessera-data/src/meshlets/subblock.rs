//! A candidate subblock of an 8×8×4 block (the block itself, one of its 4×4×4 quarters or
//! one of their 2×2×2 eighths) and the surface that one meshlet of it would hold, counted
//! the way the region analysis counts it and laid out the way extraction emits it.
//!
//! Vertex ownership follows Parallel Marching Blocks: the grid edge from sample `p` one step
//! along an axis belongs to the cell whose minimum corner is `p`. A subblock's meshlet holds
//! one vertex per crossed edge of its closed box: the edges owned by its core cells, plus
//! those owned by the padding cells just beyond its max faces that lie on those faces. Every
//! such edge is an edge of at least one occupied core cell, whose triangles use it, so no
//! vertex is left unused and none is repeated. A padding cell's edges that leave the box (the
//! x edge of a cell beyond the max x face, say) are not counted: no core cell's triangle
//! uses them, and padding cells are there only to supply the vertices of the triangles
//! inside the subblock (paper C §3.1).

use crate::marching_cubes::{case_of, cell_values, AmbiguityRule};
use crate::mc_tables::mc_tables;
use crate::meshlets::format::{MAX_OCCUPIED_CELLS, MAX_TRIANGLES, MAX_VERTICES};
use crate::meshlets::morton::{cell_of_code, BLOCK_CELL_COUNT};
use crate::volume::Volume;

/// Cells in a subblock at each level of the partition, largest first: 8×8×4, 4×4×4, 2×2×2.
pub const SUBBLOCK_CELL_COUNTS: [u32; 3] = [BLOCK_CELL_COUNT, 64, 8];

/// A run of Morton codes of one block: because of the code's bit order, each run of
/// [`SUBBLOCK_CELL_COUNTS`] length aligned to its length is a box of cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Subblock {
    /// Minimum cell of the block.
    pub block_origin: [u32; 3],
    pub first_code: u32,
    pub code_count: u32,
}

impl Subblock {
    pub fn whole_block(block_origin: [u32; 3]) -> Subblock {
        Subblock {
            block_origin,
            first_code: 0,
            code_count: BLOCK_CELL_COUNT,
        }
    }

    /// Minimum cell, in the volume's cells.
    pub fn origin(&self) -> [u32; 3] {
        let local = cell_of_code(self.first_code);
        std::array::from_fn(|a| self.block_origin[a] + local[a])
    }

    /// Cells along each axis, before clipping to the volume.
    pub fn size(&self) -> [u32; 3] {
        let last = (self.first_code + self.code_count).saturating_sub(1);
        let (lo, hi) = (cell_of_code(self.first_code), cell_of_code(last));
        std::array::from_fn(|a| hi[a] - lo[a] + 1)
    }

    /// The subblocks of the next smaller level that tile this one, in Morton order; none
    /// for the smallest.
    pub fn parts(&self) -> impl Iterator<Item = Subblock> {
        let level = SUBBLOCK_CELL_COUNTS
            .iter()
            .position(|&n| n == self.code_count);
        let (count, part) = match level.and_then(|l| SUBBLOCK_CELL_COUNTS.get(l + 1)) {
            Some(&part) => (self.code_count / part, part),
            None => (0, 0),
        };
        let whole = *self;
        (0..count).map(move |k| Subblock {
            first_code: whole.first_code + k * part,
            code_count: part,
            ..whole
        })
    }
}

/// A crossed grid edge: from sample `start` one step along `axis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GridEdge {
    pub start: [u32; 3],
    pub axis: usize,
}

/// An occupied core cell and its marching-cubes table row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SurfaceCell {
    pub cell: [u32; 3],
    pub row: usize,
}

/// What one meshlet of a subblock would hold.
#[derive(Debug, Clone, PartialEq)]
pub struct SubblockSurface {
    pub subblock: Subblock,
    /// Occupied core cells (those with a crossed edge) in Morton order.
    pub cells: Vec<SurfaceCell>,
    /// The meshlet's vertices in output order: the crossed edges owned by the occupied core
    /// cells (in their order, x, y, z edge each), then those owned by padding cells, the
    /// padding cells taken x fastest over the box.
    pub edges: Vec<GridEdge>,
    pub triangle_count: u32,
}

impl SubblockSurface {
    /// Classifies the cells of `subblock` inside `volume` and collects its crossed edges.
    pub fn scan(volume: &Volume, iso: f32, rule: AmbiguityRule, subblock: Subblock) -> Self {
        let tables = mc_tables();
        let (lo, hi) = cell_box(volume, &subblock);
        let mut surface = SubblockSurface {
            subblock,
            cells: Vec::new(),
            edges: Vec::new(),
            triangle_count: 0,
        };
        for code in subblock.first_code..subblock.first_code + subblock.code_count {
            let local = cell_of_code(code);
            let cell: [u32; 3] = std::array::from_fn(|a| subblock.block_origin[a] + local[a]);
            if (0..3).any(|a| cell[a] >= hi[a]) {
                continue;
            }
            let values = cell_values(volume, cell[0], cell[1], cell[2]);
            let case = case_of(&values, iso);
            if tables.edge_mask[usize::from(case)] == 0 {
                continue;
            }
            let row = tables.row(case, rule.joined_faces(case, &values, iso));
            surface.triangle_count += u32::from(tables.tri_count[row]);
            surface.cells.push(SurfaceCell { cell, row });
        }
        // Cells without a crossing own no crossed edge, so the occupied ones suffice.
        let core = surface.cells.iter().map(|c| c.cell);
        let padding = box_points(lo, hi).filter(|p| (0..3).any(|a| p[a] == hi[a]));
        let mut edges = Vec::new();
        for start in core.chain(padding) {
            for axis in 0..3 {
                if start[axis] < hi[axis] && edge_crosses(volume, start, axis, iso) {
                    edges.push(GridEdge { start, axis });
                }
            }
        }
        surface.edges = edges;
        surface
    }

    pub fn vertex_count(&self) -> u32 {
        self.edges.len() as u32
    }

    pub fn occupied_cell_count(&self) -> u32 {
        self.cells.len() as u32
    }

    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// Whether one meshlet can hold it.
    pub fn fits(&self) -> bool {
        self.vertex_count() <= MAX_VERTICES
            && self.triangle_count <= MAX_TRIANGLES
            && self.occupied_cell_count() <= MAX_OCCUPIED_CELLS
    }
}

/// The subblock's sample box clipped to the volume: `lo ..= hi` per axis, cells `lo .. hi`.
/// Empty (`lo >= hi` on some axis) when the subblock lies past the volume's last cell.
pub fn cell_box(volume: &Volume, subblock: &Subblock) -> ([u32; 3], [u32; 3]) {
    let (origin, size, dims) = (subblock.origin(), subblock.size(), volume.dims());
    let hi = std::array::from_fn(|a| (origin[a] + size[a]).min(dims[a].saturating_sub(1)));
    (origin, hi)
}

/// Sample points `lo ..= hi`, x fastest; none when the box is empty.
fn box_points(lo: [u32; 3], hi: [u32; 3]) -> impl Iterator<Item = [u32; 3]> {
    let empty = (0..3).any(|a| lo[a] >= hi[a]);
    let range = move |a: usize| lo[a]..if empty { lo[a] } else { hi[a] + 1 };
    range(2).flat_map(move |z| range(1).flat_map(move |y| range(0).map(move |x| [x, y, z])))
}

/// Whether the samples at either end of the edge lie on different sides of `iso`, as
/// marching cubes classifies corners (below is `< iso`).
fn edge_crosses(volume: &Volume, start: [u32; 3], axis: usize, iso: f32) -> bool {
    let [a, b] = edge_values(volume, GridEdge { start, axis });
    (a < iso) != (b < iso)
}

/// Sample values at the edge's start and end.
pub fn edge_values(volume: &Volume, edge: GridEdge) -> [f32; 2] {
    let [x, y, z] = edge.start;
    let mut end = edge.start;
    end[edge.axis] += 1;
    [volume.texel(x, y, z), volume.texel(end[0], end[1], end[2])]
}
