//! Vertices and tets renumbered along a Morton (Z-order) curve, so that tets a ray visits one
//! after the other, and their vertices, sit close together in memory.
//!
//! Morton rather than Hilbert: the code is three bit interleavings (the shaders share the same
//! helper), and the Hilbert curve's better locality matters little here because a ray's next
//! tet is a face neighbour, which both curves keep within a few cache lines.

use glam::Vec3;

use crate::tet::topology::NO_NEIGHBOUR;
use crate::tet::TetMesh;

/// Bits per axis of the quantized positions (3 × 21 = 63 bits of code).
const BITS_PER_AXIS: u32 = 21;

/// A renumbering of a mesh's vertices and tets: `new_*_of_old[old] = new`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MortonOrder {
    pub new_vertex_of_old: Vec<u32>,
    pub new_tet_of_old: Vec<u32>,
}

/// The Morton order of `mesh`: vertices by their position's code, tets by their centroid's,
/// ties kept in input order. Vertex indices must be in range.
pub fn morton_order(mesh: &TetMesh) -> MortonOrder {
    let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
    let code = |p: Vec3| morton_code(p, lo, hi);
    let vertex_codes: Vec<u64> = mesh.vertices.iter().map(|p| code(Vec3::from(*p))).collect();
    let tet_codes: Vec<u64> = mesh
        .tets
        .iter()
        .map(|t| {
            let centroid = t
                .iter()
                .map(|&v| Vec3::from(mesh.vertices[v as usize]))
                .sum::<Vec3>()
                * 0.25;
            code(centroid)
        })
        .collect();
    MortonOrder {
        new_vertex_of_old: rank_by(&vertex_codes),
        new_tet_of_old: rank_by(&tet_codes),
    }
}

impl MortonOrder {
    /// `mesh` renumbered: vertices, scalars, tets (with their vertex ids), absorption and
    /// regions. Each tet keeps its vertex order, hence its orientation.
    pub fn apply(&self, mesh: &TetMesh) -> TetMesh {
        let vertices = scatter(&mesh.vertices, &self.new_vertex_of_old);
        let scalars = mesh
            .scalars
            .as_ref()
            .map(|s| scatter(s, &self.new_vertex_of_old));
        let renumbered: Vec<[u32; 4]> = mesh
            .tets
            .iter()
            .map(|t| t.map(|v| self.new_vertex_of_old[v as usize]))
            .collect();
        TetMesh {
            vertices,
            tets: scatter(&renumbered, &self.new_tet_of_old),
            scalars,
            scalar_name: mesh.scalar_name.clone(),
            absorption: mesh
                .absorption
                .as_ref()
                .map(|a| scatter(a, &self.new_tet_of_old)),
            regions: mesh
                .regions
                .as_ref()
                .map(|r| scatter(r, &self.new_tet_of_old)),
        }
    }

    /// A neighbour table of the input mesh in the new numbering (what
    /// [`TetMesh::neighbours`] of the reordered mesh gives, without matching faces again).
    pub fn apply_to_neighbours(&self, neighbours: &[[u32; 4]]) -> Vec<[u32; 4]> {
        let renumbered: Vec<[u32; 4]> = neighbours
            .iter()
            .map(|n| {
                n.map(|t| match t {
                    NO_NEIGHBOUR => NO_NEIGHBOUR,
                    t => self.new_tet_of_old[t as usize],
                })
            })
            .collect();
        scatter(&renumbered, &self.new_tet_of_old)
    }
}

/// `out[new_of_old[i]] = items[i]`.
fn scatter<T: Copy + Default>(items: &[T], new_of_old: &[u32]) -> Vec<T> {
    let mut out = vec![T::default(); items.len()];
    for (item, &new) in items.iter().zip(new_of_old) {
        out[new as usize] = *item;
    }
    out
}

/// The position of every item when sorted by `(code, index)`.
fn rank_by(codes: &[u64]) -> Vec<u32> {
    let mut sorted: Vec<u32> = (0..codes.len() as u32).collect();
    sorted.sort_by_key(|&i| (codes[i as usize], i));
    let mut rank = vec![0; codes.len()];
    for (new, &old) in sorted.iter().enumerate() {
        rank[old as usize] = new as u32;
    }
    rank
}

/// The Morton code of `p` quantized over the box `lo`–`hi`.
fn morton_code(p: Vec3, lo: Vec3, hi: Vec3) -> u64 {
    let cells = ((1u32 << BITS_PER_AXIS) - 1) as f32;
    let extent = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let q = ((p - lo) / extent).clamp(Vec3::ZERO, Vec3::ONE) * cells;
    spread_bits(q.x as u64) | spread_bits(q.y as u64) << 1 | spread_bits(q.z as u64) << 2
}

/// The low 21 bits of `x` moved to every third bit.
fn spread_bits(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
#[path = "morton_tests.rs"]
mod tests;
