//! The PMB output: per block a run of vertices and a run of 16-bit indices local to it.

use std::collections::HashSet;

use crate::clusters::{self, ClusterRanges};
use crate::error::{DataError, Result};
use crate::mesh::TriangleMesh;

/// One block's share of a [`PmbMesh`].
///
/// `#[repr(C)]` of 4-byte fields, as the GPU writes it.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PmbBlock {
    /// The block's coordinate in blocks: its cells start at `block * block_size`.
    pub block: [u32; 3],
    /// First vertex in the mesh's vertex arrays; local indices count from it.
    pub first_vertex: u32,
    pub vertex_count: u32,
    /// First entry of [`PmbMesh::indices`] (three per triangle).
    pub first_index: u32,
    pub triangle_count: u32,
}

/// An isosurface as PMB blocks. Positions are in grid coordinates (sample `(x, y, z)` at
/// `(x, y, z)`) and triangles face the way [`crate::marching_cubes`]'s do. A vertex on a face
/// between two blocks is in both; within one block no crossed edge has two vertices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PmbMesh {
    /// Cells per block along x, y and z.
    pub block_size: [u32; 3],
    pub positions: Vec<[f32; 3]>,
    /// One per position.
    pub normals: Vec<[f32; 3]>,
    /// Three per triangle, each an index into its block's vertex range.
    pub indices: Vec<u16>,
    /// Blocks with at least one triangle, in any order.
    pub blocks: Vec<PmbBlock>,
}

impl PmbMesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Every triangle's corner positions, block by block. Triangles whose indices reach
    /// outside their block or the arrays are skipped; [`Self::validate`] reports them.
    pub fn triangles(&self) -> impl Iterator<Item = [[f32; 3]; 3]> + '_ {
        self.global_triangles()
            .map(|t| t.map(|i| self.positions[i as usize]))
    }

    /// The same triangles as one indexed mesh over the same vertices (indices made global;
    /// vertices on block faces stay repeated). Out-of-range triangles are dropped as in
    /// [`Self::triangles`].
    pub fn to_triangle_mesh(&self) -> TriangleMesh {
        clusters::triangle_mesh(&self.positions, &self.normals, self.global_triangles())
    }

    /// One indexed mesh with the vertices that neighbouring blocks both hold merged: two
    /// blocks compute the vertex of a shared edge alike, so equal positions (bit for bit)
    /// are one vertex, the first one's normal kept. Marching cubes' mesh of the same surface
    /// has as many vertices, unless a sample equals the isovalue (its vertices then coincide).
    pub fn welded(&self) -> TriangleMesh {
        clusters::welded(&self.positions, &self.normals, self.global_triangles())
    }

    /// Checks what every consumer relies on: one normal per position, ranges inside the
    /// arrays, each block listed once and holding at most a block's worth of vertices,
    /// indices inside their block, every vertex of a block used by one of its triangles and
    /// none repeated (two vertices at one position), and every vertex inside its block's
    /// closed box.
    ///
    /// As for meshlets, two vertices share a position only where a sample equals the
    /// isovalue exactly; this check reports them as repeated.
    pub fn validate(&self) -> Result<()> {
        let invalid = |what: String| Err(DataError::Invalid(format!("PMB mesh: {what}")));
        let (positions, indices) = (self.positions.len(), self.indices.len());
        if let Err(why) = clusters::check_arrays(positions, self.normals.len(), indices) {
            return invalid(why);
        }
        let mut listed = HashSet::with_capacity(self.blocks.len());
        for b in &self.blocks {
            if !listed.insert(b.block) {
                return invalid(format!("block {:?} listed twice", b.block));
            }
            if let Err(why) = self.check_block(b) {
                return invalid(format!("block {:?}: {why}", b.block));
            }
        }
        Ok(())
    }

    fn check_block(&self, b: &PmbBlock) -> std::result::Result<(), String> {
        let most = 3 * self.block_size.iter().map(|&s| s + 1).product::<u32>();
        if b.vertex_count > most {
            return Err(format!(
                "{} vertices, more than its box's {most} edges",
                b.vertex_count
            ));
        }
        let ranges = self.ranges(b)?;
        clusters::check_indices(&self.indices[ranges.indices], ranges.vertices.len())?;
        let corner = |k: u32| -> [f32; 3] {
            std::array::from_fn(|a| {
                (u64::from(b.block[a]) + u64::from(k)) as f32 * self.block_size[a] as f32
            })
        };
        clusters::check_positions(
            &self.positions[ranges.vertices],
            "box",
            (corner(0), corner(1)),
        )
    }

    /// The block's vertex and index ranges, or which one leaves its array.
    fn ranges(&self, b: &PmbBlock) -> std::result::Result<ClusterRanges, &'static str> {
        ClusterRanges::new(
            (b.first_vertex, b.vertex_count),
            (u64::from(b.first_index), 3 * u64::from(b.triangle_count)),
            self.positions.len(),
            self.indices.len(),
        )
    }

    /// Triangles as indices into the vertex arrays, those out of range left out.
    fn global_triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        let ranges = self.blocks.iter().map(|b| self.ranges(b).ok());
        clusters::global_triangles(&self.indices, ranges)
    }
}
