use super::format::{MeshletMesh, MAX_TRIANGLES, MAX_VERTICES};
use super::offline::offline_meshlets;
use crate::marching_cubes::{marching_cubes_with, AmbiguityRule};
use crate::mesh::TriangleMesh;
use crate::procedural::{generate, ProceduralKind};
use crate::volume::ScalarType;

#[test]
fn offline_meshlets_cover_the_marching_cubes_triangles() {
    let cases = [
        (ProceduralKind::Sphere, 27, 0.6123),
        (ProceduralKind::MarschnerLobb, 33, 0.5013),
    ];
    for (kind, size, iso) in cases {
        let volume = generate(kind, size, ScalarType::F32).unwrap();
        for rule in [AmbiguityRule::AsymptoticDecider, AmbiguityRule::Vtk] {
            let mesh = marching_cubes_with(&volume, iso, rule);
            let meshlets = offline_meshlets(&mesh).unwrap();
            meshlets.validate().unwrap();
            let flat = meshlets.to_triangle_mesh();
            assert!(
                flat.canonical_triangle_multiset(1e-5) == mesh.canonical_triangle_multiset(1e-5),
                "{kind:?} {rule:?}: triangles differ"
            );
            // Clusters as large as the limits allow, give or take the last one's remainder.
            let n = meshlets.meshlets.len();
            assert!(n > 1 && n < 2 * mesh.triangle_count().div_ceil(100), "{n}");
            assert!(meshlets
                .meshlets
                .iter()
                .all(|m| m.vertex_count() <= MAX_VERTICES && m.triangle_count() <= MAX_TRIANGLES));
            assert!(meshlets.meshlets.iter().any(|m| m.vertex_count() > 100));
        }
    }
}

#[test]
fn an_empty_mesh_has_no_meshlets_and_bad_indices_are_an_error() {
    assert_eq!(
        offline_meshlets(&TriangleMesh::default()).unwrap(),
        MeshletMesh::default()
    );
    let bad = TriangleMesh {
        positions: vec![glam::Vec3::ZERO; 3],
        normals: Vec::new(),
        triangles: vec![[0, 1, 3]],
    };
    let e = offline_meshlets(&bad).unwrap_err().to_string();
    assert!(e.contains("indexes past"), "{e}");
}
