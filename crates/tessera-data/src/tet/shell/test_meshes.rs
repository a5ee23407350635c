//! Meshes the shell tests share: convex, curved, non-convex with a gap, and the tetgen bunny
//! when scripts/fetch-bunny.sh has fetched it.

use crate::tet::procedural::{box_mesh, exploded, sphere_mesh};
use crate::tet::{load_tet_mesh, TetMesh};

/// Two boxes side by side along x with a gap between them (the halves x < 0 and x > 0 of a
/// box, each moved 0.5 away from the centre).
pub fn two_boxes() -> TetMesh {
    exploded(&box_mesh(2), 2, 0.5)
}

/// The meshes every test runs on, by name, each with per-vertex scalars (the bunny's height
/// where its files have none).
pub fn named_meshes() -> Vec<(&'static str, TetMesh)> {
    let mut meshes = vec![
        ("box", box_mesh(3)),
        ("sphere", sphere_mesh(3)),
        ("two boxes", two_boxes()),
    ];
    meshes.extend(bunny().map(|m| ("bunny", m)));
    meshes
}

/// The tetgen bunny, or `None` with the skip reported by the running test's name.
pub fn bunny() -> Option<TetMesh> {
    let node = tessera_test::data_file("bunny/bunny.1.node");
    if !node.exists() {
        tessera_test::skip(
            "bunny",
            &format!("{} not found (scripts/fetch-bunny.sh)", node.display()),
        );
        return None;
    }
    let mut mesh = load_tet_mesh(&node).expect("the bunny loads").0;
    if mesh.scalars.is_none() {
        mesh.scalars = Some(mesh.vertices.iter().map(|p| p[1]).collect());
    }
    Some(mesh)
}
