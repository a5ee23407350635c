//! Offline meshlet reference (paper C §4): a welded mesh, typically
//! [`crate::marching_cubes`]'s, clustered by meshoptimizer into meshlets of at most
//! [`MAX_VERTICES`] vertices and [`MAX_TRIANGLES`] triangles, in the common format. It is
//! the best-case draw reference: near-optimal meshlets, built far too slowly for real time.

use crate::error::{DataError, Result};
use crate::mesh::TriangleMesh;
use crate::meshlets::format::{bounds, Meshlet, MeshletMesh, MAX_TRIANGLES, MAX_VERTICES};

/// meshoptimizer's own limits on a meshlet (`meshopt_buildMeshlets`); ours must lie within.
const MESHOPT_MAX_VERTICES: u32 = 256;
const MESHOPT_MAX_TRIANGLES: u32 = 512;
const _: () =
    assert!(MAX_VERTICES <= MESHOPT_MAX_VERTICES && MAX_TRIANGLES <= MESHOPT_MAX_TRIANGLES);

/// Clusters `mesh` into meshlets. Each meshlet's vertices are copies of the mesh's (so
/// vertices on meshlet borders appear once per meshlet); there is no cell box, so the
/// subblock fields are zero.
pub fn offline_meshlets(mesh: &TriangleMesh) -> Result<MeshletMesh> {
    let vertex_count = mesh.positions.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .find(|t| t.iter().any(|&i| i as usize >= vertex_count))
    {
        // meshoptimizer asserts (aborts) on such indices rather than reporting them.
        return Err(DataError::Invalid(format!(
            "triangle {t:?} indexes past the mesh's {vertex_count} vertices"
        )));
    }
    let mut out = MeshletMesh::default();
    if mesh.triangles.is_empty() {
        return Ok(out);
    }
    let indices: &[u32] = bytemuck::cast_slice(&mesh.triangles);
    let position_bytes: &[u8] = bytemuck::cast_slice(&mesh.positions);
    let stride = std::mem::size_of::<glam::Vec3>();
    let adapter = meshopt::VertexDataAdapter::new(position_bytes, stride, 0)
        .map_err(|e| DataError::Invalid(format!("meshoptimizer vertex data: {e}")))?;
    // Cone weight 0: the meshlets are drawn without cone culling (paper C §3.2.2).
    let clusters = meshopt::build_meshlets(
        indices,
        &adapter,
        MAX_VERTICES as usize,
        MAX_TRIANGLES as usize,
        0.0,
    );
    let too_many = || DataError::Invalid("more than 2^32 meshlet vertices".to_string());
    for cluster in clusters.iter() {
        // Border vertices are copied into each meshlet, so the total may outgrow the mesh's.
        let vertex_offset = u32::try_from(out.positions.len()).map_err(|_| too_many())?;
        let triangle_offset = u32::try_from(out.triangle_count()).map_err(|_| too_many())?;
        for &v in cluster.vertices {
            let v = v as usize;
            out.positions.push(mesh.positions[v].to_array());
            out.normals
                .push(mesh.normals.get(v).copied().unwrap_or_default().to_array());
        }
        out.local_indices.extend_from_slice(cluster.triangles);
        let (aabb_min, aabb_max) = bounds(&out.positions[vertex_offset as usize..]);
        out.meshlets.push(Meshlet::new(
            vertex_offset,
            cluster.vertices.len() as u32,
            triangle_offset,
            (cluster.triangles.len() / 3) as u32,
            (aabb_min, aabb_max),
            [0; 3],
            [0; 3],
        ));
    }
    Ok(out)
}
