//! A shell mesh on the GPU: the vertices with their scalars, the tets in one compact layout,
//! the shell triangles in BVH leaf order and the BVH's nodes.

use crate::error::{Error, Result};
use tessera_data::tet::scalar_integral::scalar_range;
use tessera_data::tet::shell::{LayoutKind, ShellMesh, TetLayout, BVH_MAX_DEPTH};
use tessera_gpu::{vk, Buffer, Gpu};

pub struct GpuShellMesh {
    /// World xyz and, in w, the vertex's scalar as loaded (0 without scalars); the shaders map
    /// it through the scalar range, so a new range uploads nothing.
    pub vertices: Buffer,
    pub tets: Buffer,
    /// `uvec4` per shell face: the vertex ids in outward winding and the tet behind.
    pub faces: Buffer,
    pub bvh: Buffer,
    pub layout: LayoutKind,
    pub tet_count: u32,
    pub vertex_count: u32,
    /// The scalar range mapped onto [0, 1]: the mesh's own until a caller sets another.
    pub scalar_range: (f32, f32),
}

impl GpuShellMesh {
    /// `shell` with its tets in layout `kind`.
    pub fn upload(gpu: &Gpu, shell: &ShellMesh, kind: LayoutKind) -> Result<GpuShellMesh> {
        GpuShellMesh::upload_layout(gpu, shell, &*shell.layout(kind))
    }

    /// `shell` with its tets as `layout` holds them (built from the same mesh, or on purpose
    /// from another neighbour table).
    pub fn upload_layout(
        gpu: &Gpu,
        shell: &ShellMesh,
        layout: &dyn TetLayout,
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
        Ok(GpuShellMesh {
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
        self.vertices.size + self.tets.size + self.faces.size + self.bvh.size
    }
}
