//! What meshes made of clusters share — meshlets and PMB blocks: each cluster is a run of
//! the mesh's vertices and a run of triangles whose indices count from the run's first
//! vertex. The formats differ in how they describe a cluster; once it is turned into
//! [`ClusterRanges`], making the triangles global, welding and checking are the same.

use std::collections::{HashMap, HashSet};
use std::ops::Range;

use glam::Vec3;

use crate::mesh::TriangleMesh;

/// One cluster's vertex range and index range (indices, three per triangle), both inside the
/// mesh's arrays.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ClusterRanges {
    pub vertices: Range<usize>,
    pub indices: Range<usize>,
}

impl ClusterRanges {
    /// The ranges of `vertex_count` vertices from `first_vertex` and `index_count` indices
    /// from `first_index`, when both lie in arrays of `vertex_len` and `index_len` elements;
    /// else which one leaves its array.
    pub fn new(
        (first_vertex, vertex_count): (u32, u32),
        (first_index, index_count): (u64, u64),
        vertex_len: usize,
        index_len: usize,
    ) -> std::result::Result<ClusterRanges, &'static str> {
        let vertices = range(u64::from(first_vertex), u64::from(vertex_count), vertex_len);
        let indices = range(first_index, index_count, index_len);
        Ok(ClusterRanges {
            vertices: vertices.ok_or("vertex range outside the vertex arrays")?,
            indices: indices.ok_or("triangle range outside the indices")?,
        })
    }
}

/// `first .. first + count` when it lies in an array of `len` elements.
fn range(first: u64, count: u64, len: usize) -> Option<Range<usize>> {
    let end = first.checked_add(count)?;
    (end <= len as u64).then_some(first as usize..end as usize)
}

/// Every triangle of `clusters` as indices into the vertex arrays. Clusters whose ranges
/// leave the arrays (`None`) and triangles with an index past their cluster's vertices are
/// left out.
pub(crate) fn global_triangles<'a, I: Copy + Into<u32>>(
    indices: &'a [I],
    clusters: impl Iterator<Item = Option<ClusterRanges>> + 'a,
) -> impl Iterator<Item = [u32; 3]> + 'a {
    clusters.flatten().flat_map(move |c| {
        let vertices = c.vertices;
        indices[c.indices].chunks_exact(3).filter_map(move |t| {
            let global = |i: I| {
                let v = vertices.start + i.into() as usize;
                (v < vertices.end).then_some(v as u32)
            };
            Some([global(t[0])?, global(t[1])?, global(t[2])?])
        })
    })
}

/// One indexed mesh over the same vertices.
pub(crate) fn triangle_mesh(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    triangles: impl Iterator<Item = [u32; 3]>,
) -> TriangleMesh {
    TriangleMesh {
        positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
        normals: normals.iter().map(|&n| Vec3::from(n)).collect(),
        triangles: triangles.collect(),
    }
}

/// One indexed mesh whose vertices at the same position (bit for bit) are one, the first
/// one's normal kept: the copies of a vertex that neighbouring clusters both hold merge.
pub(crate) fn welded(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    triangles: impl Iterator<Item = [u32; 3]>,
) -> TriangleMesh {
    let mut first_at: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    let mut mesh = TriangleMesh::default();
    let remap: Vec<u32> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            *first_at.entry(p.map(f32::to_bits)).or_insert_with(|| {
                mesh.positions.push(Vec3::from(*p));
                mesh.normals
                    .push(Vec3::from(normals.get(i).copied().unwrap_or_default()));
                (mesh.positions.len() - 1) as u32
            })
        })
        .collect();
    mesh.triangles = triangles.map(|t| t.map(|i| remap[i as usize])).collect();
    mesh
}

/// The checks of the whole arrays: one normal per position, whole triangles.
pub(crate) fn check_arrays(
    positions: usize,
    normals: usize,
    indices: usize,
) -> std::result::Result<(), String> {
    if normals != positions {
        return Err(format!("{normals} normals for {positions} positions"));
    }
    if !indices.is_multiple_of(3) {
        return Err(format!(
            "{indices} indices is not a whole number of triangles"
        ));
    }
    Ok(())
}

/// Checks that each of a cluster's `indices` names one of its vertices and that every vertex
/// is used by a triangle.
pub(crate) fn check_indices<I: Copy + Into<u32>>(
    indices: &[I],
    vertex_count: usize,
) -> std::result::Result<(), String> {
    let mut used = vec![false; vertex_count];
    for &i in indices {
        let i = i.into();
        let slot = used
            .get_mut(i as usize)
            .ok_or_else(|| format!("local index {i} of {vertex_count} vertices"))?;
        *slot = true;
    }
    match used.iter().position(|u| !u) {
        Some(i) => Err(format!("vertex {i} is used by no triangle")),
        None => Ok(()),
    }
}

/// Checks what a producer gives a cluster's vertices: no position twice, each inside the
/// closed box `lo..hi` (`what` names it in the message).
pub(crate) fn check_positions(
    positions: &[[f32; 3]],
    what: &str,
    (lo, hi): ([f32; 3], [f32; 3]),
) -> std::result::Result<(), String> {
    let mut seen = HashSet::with_capacity(positions.len());
    for (i, p) in positions.iter().enumerate() {
        if !seen.insert(p.map(f32::to_bits)) {
            return Err(format!("vertex {i} repeats position {p:?}"));
        }
        if (0..3).any(|a| !(lo[a] <= p[a] && p[a] <= hi[a])) {
            return Err(format!(
                "vertex {i} at {p:?} outside the {what} {lo:?}..{hi:?}"
            ));
        }
    }
    Ok(())
}
