//! Tests of the shell faces and the compact tet layouts.
use super::test_meshes::named_meshes;
use super::*;
use crate::tet::topology::FACE_CORNERS;
use crate::tet::topology::NO_NEIGHBOUR;

#[test]
fn layouts_take_the_papers_sizes() {
    let shell = ShellMesh::build(&crate::tet::procedural::box_mesh(1)).unwrap();
    let sizes: Vec<usize> = LayoutKind::ALL
        .iter()
        .map(|&k| shell.layout(k).bytes_per_tet())
        .collect();
    assert_eq!(sizes, [32, 20, 16]);
    for kind in LayoutKind::ALL {
        assert_eq!(LayoutKind::parse(kind.name()).unwrap(), kind);
        assert_eq!(shell.layout(kind).kind(), kind);
    }
    assert!(LayoutKind::parse("tet8").is_err());
}

/// Decodes every tet entered through every face, from the tet across it (or the shell), and
/// checks the four vertices and the neighbour across each against the mesh.
#[test]
fn every_layout_reproduces_the_vertex_ids_and_neighbour_table() {
    for (name, mesh) in named_meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        for kind in LayoutKind::ALL {
            let layout = shell.layout(kind);
            for (t, tet) in shell.mesh.tets.iter().enumerate() {
                let across = shell.neighbours[t];
                for f in 0..4 {
                    let entered = FACE_CORNERS[f].map(|c| tet[c]);
                    let decoded = layout
                        .decode(t as u32, across[f], entered)
                        .unwrap_or_else(|| panic!("{name} {kind:?}: tet {t} face {f}"));
                    assert_eq!(decoded.vertices[3], tet[f], "{name} {kind:?} tet {t}");
                    for i in 0..4 {
                        let corner = tet.iter().position(|&v| v == decoded.vertices[i]);
                        let corner = corner.expect("a vertex of the tet");
                        assert_eq!(
                            decoded.neighbours[i], across[corner],
                            "{name} {kind:?}: tet {t} entered by face {f}, across vertex {i}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn tet32_refuses_a_face_that_is_not_the_tets() {
    let shell = ShellMesh::build(&crate::tet::procedural::box_mesh(1)).unwrap();
    let layout = shell.layout(LayoutKind::Tet32);
    let tet = shell.mesh.tets[0];
    let stranger = (0..shell.mesh.vertices.len() as u32)
        .find(|v| !tet.contains(v))
        .unwrap();
    assert!(layout
        .decode(0, NO_NEIGHBOUR, [tet[0], tet[1], stranger])
        .is_none());
    assert!(layout
        .decode(99, NO_NEIGHBOUR, [tet[0], tet[1], tet[2]])
        .is_none());
}

#[test]
fn shell_faces_are_the_boundary_in_outward_winding_with_their_tets() {
    for (name, mesh) in named_meshes() {
        let shell = ShellMesh::build(&mesh).unwrap();
        let mut ours: Vec<[u32; 3]> = shell.faces.iter().map(|f| f.vertices).collect();
        let mut boundary = shell.mesh.boundary_faces();
        ours.sort_unstable();
        boundary.sort_unstable();
        assert_eq!(ours, boundary, "{name}");
        for face in &shell.faces {
            let tet = shell.mesh.tets[face.tet as usize];
            assert_eq!(
                shell.neighbours[face.tet as usize][face.face as usize],
                NO_NEIGHBOUR
            );
            assert_eq!(
                face.vertices,
                FACE_CORNERS[face.face as usize].map(|c| tet[c])
            );
            // Outward: the normal points away from the tet's opposite vertex.
            let [a, b, c] = face.vertices.map(|v| shell.world[v as usize]);
            let apex = shell.world[tet[face.face as usize] as usize];
            assert!((b - a).cross(c - a).dot(apex - a) < 0.0, "{name}");
        }
    }
}

#[test]
fn a_convex_box_has_its_six_sides_as_shell() {
    let n = 3;
    let shell = ShellMesh::build(&crate::tet::procedural::box_mesh(n)).unwrap();
    assert_eq!(shell.faces.len(), 6 * 2 * (n * n) as usize);
    let area: f64 = shell
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.vertices.map(|v| shell.world[v as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    assert!(
        (area - 6.0).abs() < 1e-9,
        "unit cube in world space: {area}"
    );
    assert!(shell
        .world
        .iter()
        .all(|p| p.abs().max_element() <= 0.5 + 1e-12));
}

#[test]
fn bad_meshes_are_refused_with_an_error() {
    let mut mesh = crate::tet::procedural::box_mesh(1);
    mesh.tets[2][1] = 999;
    let err = ShellMesh::build(&mesh).unwrap_err().to_string();
    assert!(
        err.contains("tet 2") && err.contains("out of range"),
        "{err}"
    );
    let mut mesh = crate::tet::procedural::box_mesh(1);
    mesh.vertices[3][0] = f32::NAN;
    assert!(ShellMesh::build(&mesh).is_err());
    assert!(ShellMesh::build(&TetMesh::default()).is_err());
    let mut mesh = crate::tet::procedural::box_mesh(1);
    mesh.tets.pop();
    let err = ShellMesh::build(&mesh).unwrap_err().to_string();
    assert!(err.contains("6 absorption colours for 5 tets"), "{err}");
}
