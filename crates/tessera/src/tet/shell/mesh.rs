//! A shell mesh on the GPU: the vertices with their scalars, the tets in one compact layout,
//! the shell triangles in BVH leaf order and the BVH's nodes; for passes on the ray-tracing
//! pipeline also an acceleration structure over boxes around the shell triangles (in the same
//! order).

use crate::error::{Error, Result};
use crate::path::Path;
use tessera_data::tet::scalar_integral::scalar_range;
use tessera_data::tet::shell::{LayoutKind, ShellMesh, TetLayout, BVH_MAX_DEPTH};
use tessera_gpu::{vk, AccelerationStructure, Buffer, Gpu};

pub struct GpuShellMesh {
    /// World xyz and, in w, the vertex's scalar as loaded (0 without scalars); the shaders map
    /// it through the scalar range, so a new range uploads nothing.
    pub vertices: Buffer,
    pub tets: Buffer,
    /// `uvec4` per shell face: the vertex ids in outward winding and the tet behind.
    pub faces: Buffer,
    pub bvh: Buffer,
    /// Primitive i is a box around shell face i (ray-tracing passes only).
    pub scene: Option<AccelerationStructure>,
    pub layout: LayoutKind,
    pub tet_count: u32,
    pub vertex_count: u32,
    /// The scalar range mapped onto [0, 1]: the mesh's own until a caller sets another.
    pub scalar_range: (f32, f32),
}

impl GpuShellMesh {
    /// `shell` with its tets in layout `kind`, for compute passes.
    pub fn upload(gpu: &Gpu, shell: &ShellMesh, kind: LayoutKind) -> Result<GpuShellMesh> {
        GpuShellMesh::upload_layout(gpu, shell, &*shell.layout(kind), Path::Compute)
    }

    /// `shell` with its tets in layout `kind`, for passes on `path` (the graphics path is the
    /// ray-tracing pipeline, which needs the acceleration structure).
    pub fn upload_for(
        gpu: &Gpu,
        shell: &ShellMesh,
        kind: LayoutKind,
        path: Path,
    ) -> Result<GpuShellMesh> {
        GpuShellMesh::upload_layout(gpu, shell, &*shell.layout(kind), path)
    }

    /// `shell` with its tets as `layout` holds them (built from the same mesh, or on purpose
    /// from another neighbour table), for passes on `path`.
    pub fn upload_layout(
        gpu: &Gpu,
        shell: &ShellMesh,
        layout: &dyn TetLayout,
        path: Path,
    ) -> Result<GpuShellMesh> {
        if shell.faces.is_empty() || layout.tet_count() != shell.mesh.tets.len() {
            return Err(Error::Invalid(format!(
                "shell traversal: {} shell faces, a layout of {} tets for {} tets",
                shell.faces.len(),
                layout.tet_count(),
                shell.mesh.tets.len()
            )));
        }
        // The shaders index the tets' 32-bit words with 32-bit integers.
        let words = layout.tet_count() as u64 * (layout.bytes_per_tet() / 4) as u64;
        if words > u64::from(u32::MAX) {
            return Err(Error::Invalid(format!(
                "shell traversal: {} tets in {} take more than 2^32 words",
                layout.tet_count(),
                layout.kind().name()
            )));
        }
        let bvh = shell.bvh();
        // The shaders' stack holds one entry per level (BVH_MAX_DEPTH + 1).
        debug_assert!(bvh.depth <= BVH_MAX_DEPTH);
        let scalars = shell.mesh.scalars.as_deref();
        let vertices: Vec<[f32; 4]> = shell
            .world()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let s = scalars.and_then(|s| s.get(i)).copied().unwrap_or(0.0);
                p.as_vec3().extend(s).to_array()
            })
            .collect();
        let faces: Vec<[u32; 4]> = bvh
            .faces
            .iter()
            .map(|&f| {
                let face = &shell.faces[f as usize];
                let [a, b, c] = face.vertices;
                [a, b, c, face.tet]
            })
            .collect();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let scene = match path {
            Path::Graphics => {
                Some(gpu.build_box_acceleration("shell faces", &face_boxes(&vertices, &faces))?)
            }
            Path::Compute => None,
        };
        Ok(GpuShellMesh {
            scene,
            vertices: gpu.upload_buffer(
                "shell vertices",
                bytemuck::cast_slice(&vertices),
                usage,
            )?,
            tets: gpu.upload_buffer("shell tets", layout.as_bytes(), usage)?,
            faces: gpu.upload_buffer("shell faces", bytemuck::cast_slice(&faces), usage)?,
            bvh: gpu.upload_buffer("shell bvh", bytemuck::cast_slice(&bvh.nodes), usage)?,
            layout: layout.kind(),
            tet_count: layout.tet_count() as u32,
            vertex_count: vertices.len() as u32,
            scalar_range: scalar_range(&shell.mesh).unwrap_or((0.0, 1.0)),
        })
    }

    /// Bytes on the GPU.
    pub fn bytes(&self) -> u64 {
        self.vertices.size
            + self.tets.size
            + self.faces.size
            + self.bvh.size
            + self.scene.as_ref().map_or(0, |s| s.bytes())
    }
}

/// A box around each face (`[a, b, c, tet]` vertex ids into `vertices`), widened by a
/// hundred-thousandth of the mesh's extent plus a little: the hit shaders decide with the marching's
/// own predicates, so the boxes must not lose a ray grazing a face's edge to rounding in the
/// box test, nor a face lying in an axis plane to a box of zero thickness.
fn face_boxes(vertices: &[[f32; 4]], faces: &[[u32; 4]]) -> Vec<[f32; 6]> {
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for v in vertices {
        for axis in 0..3 {
            lo[axis] = lo[axis].min(v[axis]);
            hi[axis] = hi[axis].max(v[axis]);
        }
    }
    let extent = (0..3).map(|a| (hi[a] - lo[a]).abs()).fold(0.0f32, f32::max);
    let pad = extent * 1e-5 + f32::MIN_POSITIVE.sqrt();
    faces
        .iter()
        .map(|face| {
            let mut b = [f32::MAX, f32::MAX, f32::MAX, f32::MIN, f32::MIN, f32::MIN];
            for &id in &face[..3] {
                let v = vertices.get(id as usize).copied().unwrap_or_default();
                for axis in 0..3 {
                    b[axis] = b[axis].min(v[axis]);
                    b[axis + 3] = b[axis + 3].max(v[axis]);
                }
            }
            for axis in 0..3 {
                b[axis] -= pad + b[axis].abs() * 4.0 * f32::EPSILON;
                b[axis + 3] += pad + b[axis + 3].abs() * 4.0 * f32::EPSILON;
            }
            b
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::face_boxes;

    #[test]
    fn face_boxes_hold_their_face_with_room() {
        let vertices = [
            [0.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, -3.0, 0.0],
        ];
        let boxes = face_boxes(&vertices, &[[0, 1, 2, 0], [1, 2, 3, 0]]);
        assert_eq!(boxes.len(), 2);
        // A face in the plane z = 0 still gets a box of some thickness.
        let flat = boxes[0];
        assert!(flat[2] < 0.0 && flat[5] > 0.0, "{flat:?}");
        assert!(flat[0] < 0.0 && flat[3] > 1.0 && flat[4] > 2.0 && flat[4] < 2.001);
        let slanted = boxes[1];
        assert!(slanted[0] < 0.0 && slanted[2] < -3.0 && slanted[1] < 0.0 && slanted[4] > 2.0);
    }
}
