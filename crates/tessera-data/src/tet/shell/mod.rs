//! CPU foundation of ray-traced shell traversal (paper B, after Aman et al. for the marching):
//! the mesh reordered along a Morton curve, its shell (boundary triangles, each with its tet),
//! the compact tet layouts Tet32 / Tet20 / Tet16, the shell-to-shell traversal of Alg. 1 with
//! tet marching in a ray-centric 2-D projection, and emission–absorption rendering and shadow
//! transmittance on top of it. This is the ground truth the GPU paths will be held to.
//!
//! Everything works in world space as [`MeshFrame::of`] places the mesh, so results compare
//! directly with interval shading's references ([`crate::tet::optical`]).
//!
//! # GPU buffers (what the compute path reads; a ray-generation shader would read the same)
//! - **Vertices**: `vec4` per vertex in the Morton order of [`ShellMesh::mesh`]: world-space
//!   position (f32) and the scalar in `w`, so one 16-byte load serves projection and shading
//!   (the paper keeps scalars beside the vertices for the same reason). The scalar is kept as
//!   loaded and mapped onto [0, 1] through a range in push constants, so a new range uploads
//!   nothing.
//! - **Tets**: one array of the chosen layout, `#[repr(C)]` as [`Tet32`] (32 bytes in std430
//!   as `uvec3 v; uint vx; uvec4 n;`), [`Tet20`] (20 bytes as `uint vx; uint n[4];`: scalar
//!   arrays keep a 4-byte alignment, where a `uvec4` would pad the struct to 32) or [`Tet16`]
//!   (16 bytes as one `uvec4`: `vx, nx0, nx1, nx2`; `uint vx; uvec3 nx;` would put `nx` at
//!   offset 16). [`NO_NEIGHBOUR`] (`0xFFFF_FFFF`) marks the shell.
//! - **Shell triangles**: `uvec4` per [`ShellFace`] as the paper's index buffer: the three
//!   vertex ids in outward winding and the tet in `w` (the face index is not needed: marching
//!   starts from the vertex ids), in the leaf order of [`ShellMesh::bvh`], whose [`BvhNode`]s
//!   the compute path walks. A bottom-level acceleration structure would be built over the
//!   vertex buffer with these indices (stride 16).
//! - **Per ray**: the traversal needs only the current tet, the tet it came from (Tet16), the
//!   three entered-face vertex ids and their 2-D projections, so the state fits registers.
//!
//! [`NO_NEIGHBOUR`]: crate::tet::topology::NO_NEIGHBOUR

use glam::{DVec3, Vec3};

use super::optical::MeshFrame;
use super::topology::NO_NEIGHBOUR;
use super::TetMesh;
use crate::error::{DataError, Result};

mod bvh;
mod effects;
mod faces;
mod layouts;
mod lighting;
mod march;
mod morton;
mod projection;
mod render;
mod shell_hits;
mod tet16;
mod tet20;
mod tet32;
mod traverse;

pub use bvh::{build_bvh, BvhNode, ShellBvh, BVH_LEAF_FACES, BVH_MAX_DEPTH};
pub use effects::{
    ao_directions, ao_normal, ao_pattern, gradient_weight, hemisphere_frame, AmbientOcclusion,
    GroundPlane, SecondaryStats, ShellEffects, StretchLighting, AO_FALLBACK_NORMAL,
    DEFAULT_AO_RADIUS, GRADIENT_RAMP, GRADIENT_THRESHOLD, GROUND_ALBEDO, GROUND_GAP,
    GROUND_HALF_EXTENT, MAX_AO_SAMPLES, VOLUME_AMBIENT,
};
pub use faces::{shell_faces, ShellFace};
pub use layouts::{build_layout, DecodedTet, LayoutKind, TetLayout};
pub use lighting::TetLighting;
pub use morton::{morton_order, MortonOrder};
pub use render::{
    render_shell_effects_reference, render_shell_reference, shadow_transmittance, Light,
    LitStretch, ShellIntegrator, ShellRender, ShellScene,
};
pub use tet16::{Tet16, Tet16Mesh};
pub use tet20::{Tet20, Tet20Mesh};
pub use tet32::{Tet32, Tet32Mesh};
pub use traverse::{
    trace_segments, traverse, Ray, Segment, SegmentEnd, Step, StepVisitor, TraversalOptions,
    TraversalStats,
};

/// A tet mesh prepared for shell traversal: reordered along a Morton curve, with its face
/// neighbours, shell faces and world-space vertex positions.
#[derive(Clone, Debug)]
pub struct ShellMesh {
    /// The input mesh with vertices and tets (and their scalars and attributes) in Morton
    /// order.
    pub mesh: TetMesh,
    /// How the input's vertices and tets were renumbered.
    pub order: MortonOrder,
    /// Per tet of [`ShellMesh::mesh`], the tet across each face (face `i` opposite vertex `i`).
    pub neighbours: Vec<[u32; 4]>,
    /// The boundary triangles, in outward winding.
    pub faces: Vec<ShellFace>,
    /// Where the mesh sits in world space (the same as for the input mesh).
    pub frame: MeshFrame,
    /// Vertex positions in world space, in `f64` as the references compute.
    pub(crate) world: Vec<DVec3>,
}

impl ShellMesh {
    /// Reorders `mesh` and builds its connectivity. Errors on an empty mesh, vertex indices
    /// out of range, non-finite coordinates or attributes of the wrong length; degenerate and
    /// inverted tets are kept (the traversal's loop guard copes with them).
    pub fn build(mesh: &TetMesh) -> Result<ShellMesh> {
        check(mesh)?;
        let order = morton_order(mesh);
        let reordered = order.apply(mesh);
        let neighbours = reordered.neighbours();
        let faces = shell_faces(&reordered.tets, &neighbours);
        let frame = MeshFrame::of(&reordered);
        let world = reordered
            .vertices
            .iter()
            .map(|p| frame.to_world(Vec3::from(*p)).as_dvec3())
            .collect();
        Ok(ShellMesh {
            mesh: reordered,
            order,
            neighbours,
            faces,
            frame,
            world,
        })
    }

    /// Vertex positions in world space (each an `f32` point widened to `f64`).
    pub fn world(&self) -> &[DVec3] {
        &self.world
    }

    /// The world-space bounding box of the vertices.
    pub fn world_bounds(&self) -> (DVec3, DVec3) {
        self.world.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// The compact layout `kind` of this mesh's tets.
    pub fn layout(&self, kind: LayoutKind) -> Box<dyn TetLayout> {
        build_layout(kind, &self.mesh.tets, &self.neighbours)
    }
}

/// What the traversal needs to index safely; the full [`TetMesh::validate`] would also
/// reorient tets, which is the loaders' business.
fn check(mesh: &TetMesh) -> Result<()> {
    let invalid = |m: String| Err(DataError::Invalid(format!("shell traversal: {m}")));
    if mesh.tets.is_empty() {
        return invalid("the mesh has no tetrahedra".into());
    }
    let n = mesh.vertices.len();
    // Tet ids share u32 with the NO_NEIGHBOUR marker.
    if mesh.tets.len() >= NO_NEIGHBOUR as usize || n >= NO_NEIGHBOUR as usize {
        return invalid(format!(
            "{} tets and {n} vertices do not fit 32-bit ids",
            mesh.tets.len()
        ));
    }
    if let Some(t) = mesh
        .tets
        .iter()
        .position(|tet| tet.iter().any(|&v| v as usize >= n))
    {
        return invalid(format!(
            "tet {t} has a vertex index out of range ({n} vertices)"
        ));
    }
    if let Some(v) = mesh
        .vertices
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return invalid(format!("vertex {v} has a non-finite coordinate"));
    }
    let lengths = [
        (
            "scalars",
            mesh.scalars.as_ref().map(Vec::len),
            n,
            "vertices",
        ),
        (
            "absorption colours",
            mesh.absorption.as_ref().map(Vec::len),
            mesh.tets.len(),
            "tets",
        ),
        (
            "regions",
            mesh.regions.as_ref().map(Vec::len),
            mesh.tets.len(),
            "tets",
        ),
    ];
    for (what, len, want, of) in lengths {
        if let Some(len) = len.filter(|&l| l != want) {
            return invalid(format!("{len} {what} for {want} {of}"));
        }
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod test_meshes;

#[cfg(test)]
#[path = "layouts_tests.rs"]
mod layouts_tests;

#[cfg(test)]
#[path = "traverse_tests.rs"]
mod traverse_tests;

#[cfg(test)]
#[path = "bvh_tests.rs"]
mod bvh_tests;

#[cfg(test)]
#[path = "render_tests.rs"]
mod render_tests;

#[cfg(test)]
#[path = "effects_tests.rs"]
mod effects_tests;
