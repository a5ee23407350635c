//! The PMB output: per block a run of vertices and a run of 16-bit indices local to it.

use std::collections::{HashMap, HashSet};
use std::ops::Range;

use glam::Vec3;

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
        TriangleMesh {
            positions: self.positions.iter().map(|&p| Vec3::from(p)).collect(),
            normals: self.normals.iter().map(|&n| Vec3::from(n)).collect(),
            triangles: self.global_triangles().collect(),
        }
    }

    /// One indexed mesh with the vertices that neighbouring blocks both hold merged: two
    /// blocks compute the vertex of a shared edge alike, so equal positions (bit for bit)
    /// are one vertex, the first one's normal kept. Marching cubes' mesh of the same surface
    /// has as many vertices, unless a sample equals the isovalue (its vertices then coincide).
    pub fn welded(&self) -> TriangleMesh {
        let mut index_of: HashMap<[u32; 3], u32> = HashMap::new();
        let mut mesh = TriangleMesh::default();
        let mut remap = Vec::with_capacity(self.positions.len());
        for (i, p) in self.positions.iter().enumerate() {
            let id = *index_of.entry(p.map(f32::to_bits)).or_insert_with(|| {
                mesh.positions.push(Vec3::from(*p));
                let normal = self.normals.get(i).copied().unwrap_or_default();
                mesh.normals.push(Vec3::from(normal));
                mesh.positions.len() as u32 - 1
            });
            remap.push(id);
        }
        mesh.triangles = self
            .global_triangles()
            .map(|t| t.map(|i| remap[i as usize]))
            .collect();
        mesh
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
        if self.normals.len() != self.positions.len() {
            return invalid(format!(
                "{} normals for {} positions",
                self.normals.len(),
                self.positions.len()
            ));
        }
        if !self.indices.len().is_multiple_of(3) {
            return invalid(format!(
                "{} indices is not a whole number of triangles",
                self.indices.len()
            ));
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
        let (vertices, indices) = self
            .ranges(b)
            .ok_or_else(|| "ranges outside the arrays".to_string())?;
        let mut used = vec![false; vertices.len()];
        for &i in &self.indices[indices] {
            let slot = used
                .get_mut(usize::from(i))
                .ok_or_else(|| format!("local index {i} of {} vertices", b.vertex_count))?;
            *slot = true;
        }
        if let Some(i) = used.iter().position(|u| !u) {
            return Err(format!("vertex {i} is used by no triangle"));
        }
        let corner = |k: u32| -> [f32; 3] {
            std::array::from_fn(|a| {
                (u64::from(b.block[a]) + u64::from(k)) as f32 * self.block_size[a] as f32
            })
        };
        let (lo, hi) = (corner(0), corner(1));
        let mut seen = HashSet::with_capacity(vertices.len());
        for (i, p) in self.positions[vertices].iter().enumerate() {
            if !seen.insert(p.map(f32::to_bits)) {
                return Err(format!("vertex {i} repeats position {p:?}"));
            }
            if (0..3).any(|a| !(lo[a] <= p[a] && p[a] <= hi[a])) {
                return Err(format!(
                    "vertex {i} at {p:?} outside the box {lo:?}..{hi:?}"
                ));
            }
        }
        Ok(())
    }

    /// The block's vertex range and index range, when both lie in the arrays.
    fn ranges(&self, b: &PmbBlock) -> Option<(Range<usize>, Range<usize>)> {
        let vertices = range(b.first_vertex, b.vertex_count, self.positions.len())?;
        let index_count = b.triangle_count.checked_mul(3)?;
        let indices = range(b.first_index, index_count, self.indices.len())?;
        Some((vertices, indices))
    }

    /// Triangles as indices into the vertex arrays, those out of range left out.
    fn global_triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.blocks.iter().flat_map(move |b| {
            let indices = self
                .ranges(b)
                .map_or(&[][..], |(_, indices)| &self.indices[indices]);
            indices.chunks_exact(3).filter_map(move |t| {
                let global = |i: u16| {
                    let inside = u32::from(i) < b.vertex_count;
                    inside.then(|| b.first_vertex.checked_add(u32::from(i)))?
                };
                Some([global(t[0])?, global(t[1])?, global(t[2])?])
            })
        })
    }
}

/// `first .. first + count` when it lies in an array of `len` elements.
fn range(first: u32, count: u32, len: usize) -> Option<Range<usize>> {
    let start = first as usize;
    let end = start.checked_add(count as usize)?;
    (end <= len).then_some(start..end)
}
