//! Tests of the Gmsh loader and writer.
use super::*;
use crate::test_files::test_path;
use crate::tet::procedural::box_mesh;
use crate::tet::tests::{load_error, two_tets, write_text};

#[test]
fn round_trip() {
    let mut plain = two_tets();
    plain.absorption = None;
    for mesh in [plain, {
        let mut b = box_mesh(3);
        b.absorption = None;
        b
    }] {
        let path = test_path("rt.msh");
        write_msh41(&mesh, &path).expect("write");
        let (back, report) = crate::tet::load_tet_mesh(&path).expect("load");
        assert_eq!(report, MeshReport::default());
        assert_eq!(back, mesh);
    }
}

const NODES: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"a b\"\n$EndPhysicalNames\n\
                     $Nodes\n2 5 10 50\n0 1 0 1\n50\n1 1 1\n3 2 1 4\n10\n20\n30\n40\n\
                     0 0 0 0.5 0.5 0.5\n1 0 0 0.5 0.5 0.5\n0 1 0 0.5 0.5 0.5\n0 0 1 0.5 0.5 0.5\n$EndNodes\n";

#[test]
fn blocks_tags_and_skipped() {
    let text = format!(
        "{NODES}$Elements\n2 3 1 3\n2 4 2 1\n1 10 20 30\n3 9 4 2\n2 10 20 40 30\n3 50 20 40 30\n$EndElements\n"
    );
    let path = write_text("b.msh", &text);
    let (mesh, report) = load_msh(&path).expect("load");
    assert_eq!((report.skipped_cells, report.reoriented), (1, 1));
    assert_eq!(mesh.tets.len(), 2);
    assert_eq!(mesh.tets[0], [1, 2, 3, 4]);
    assert_eq!(mesh.regions, Some(vec![9, 9]));
    assert_eq!(mesh.vertices[0], [1.0, 1.0, 1.0]);
}

#[test]
fn bad_files() {
    let elements =
        |body: &str| format!("{NODES}$Elements\n1 1 1 1\n3 1 4 1\n{body}\n$EndElements\n");
    let cases = [
        (elements("1 10 20 30 77"), "line 26", "node tag 77"),
        (elements("1 10 20 30"), "line 26", "expected 4"),
        (
            format!("{NODES}$Elements\n1 2 1 2\n3 1 4 1\n1 10 20 30 40\n$EndElements\n"),
            "line",
            "announces 2",
        ),
        (
            format!("{NODES}$Elements\n1 1 1 1\n3 1 4 1\n"),
            "line",
            "ends inside",
        ),
        (
            "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n".to_string(),
            "line 2",
            "binary msh not supported",
        ),
        (
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n".to_string(),
            "line 2",
            "4.1",
        ),
        (
            format!("{NODES}$Elements\n1 1 1 1\n2 1 2 1\n1 10 20 30\n$EndElements\n"),
            "",
            "empty mesh",
        ),
        (
            elements("1 10 20 30 40").replace("0 0 1 0.5", "0 0 nan 0.5"),
            "vertex 4",
            "non-finite",
        ),
        ("$Nodes\n".to_string(), "line 1", "$MeshFormat"),
    ];
    for (text, place, what) in cases {
        let path = write_text("bad.msh", &text);
        let message = load_error(load_msh(&path), &path);
        assert!(
            message.contains(place) && message.contains(what),
            "{message}"
        );
    }
}
