//! Tests of the Gmsh loader and writer.
use super::*;
use crate::test_files::test_path;
use crate::tet::procedural::box_mesh;
use crate::tet::tests::{data_file, load_error, two_tets, write_text};

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
            "byte 20",
            "binary word 1",
        ),
        (
            "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n".to_string(),
            "line 2",
            "4.1 or 2.2",
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

/// The mesh every hand-made Gmsh test file holds: a triangle (skipped) and two tets in
/// entities 7 and 8, with a temperature per node.
fn check_reference_mesh(name: &str) {
    let (mesh, report) = load_msh(&data_file(name)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((report.skipped_cells, report.reoriented), (1, 0), "{name}");
    assert_eq!(mesh.tets, vec![[0, 1, 2, 3], [4, 1, 3, 2]], "{name}");
    assert_eq!(mesh.vertices[4], [1.0, 1.0, 1.0], "{name}");
    assert_eq!(mesh.regions, Some(vec![7, 8]), "{name}");
    assert_eq!(mesh.scalar_name, "temperature", "{name}");
    assert_eq!(mesh.scalars, Some(vec![1.0, 2.0, 3.0, 4.0, 5.0]), "{name}");
}

#[test]
fn format_2_2_ascii_and_binary() {
    check_reference_mesh("gmsh22_ascii.msh");
    check_reference_mesh("gmsh22_binary.msh");
}

#[test]
fn format_4_1_binary_with_entities() {
    check_reference_mesh("gmsh41_binary.msh");
}

#[test]
fn bad_binary_files() {
    let good = std::fs::read(data_file("gmsh41_binary.msh")).expect("read");
    let nodes = good
        .windows(7)
        .position(|w| w == b"$Nodes\n")
        .expect("nodes")
        + 7;
    let elements = good
        .windows(10)
        .position(|w| w == b"$Elements\n")
        .expect("elements")
        + 10;
    let patch = |at: usize, bytes: &[u8]| {
        let mut b = good.clone();
        b[at..at + bytes.len()].copy_from_slice(bytes);
        b
    };
    let cases = [
        // A node count no file of this size can hold.
        (
            patch(nodes + 8, &u64::MAX.to_le_bytes()),
            "the number of nodes",
        ),
        (patch(nodes, &(1u64 << 40).to_le_bytes()), "node blocks"),
        // An element type of unknown size.
        (
            patch(elements + 32 + 8, &99i32.to_le_bytes()),
            "element type 99 is unknown",
        ),
        (good[..elements + 100].to_vec(), "file ends inside"),
    ];
    for (bytes, what) in cases {
        let path = test_path("bad.msh");
        std::fs::write(&path, bytes).expect("write");
        let message = load_error(load_msh(&path), &path);
        assert!(
            message.contains("byte ") && message.contains(what),
            "{message}"
        );
    }
    // ASCII 2.2 problems name the line.
    let text = std::fs::read_to_string(data_file("gmsh22_ascii.msh")).expect("read");
    let path = write_text(
        "bad.msh",
        &text.replace("3 4 2 2 8 50 20 40 30", "3 4 2 2 8 50 20 40 99"),
    );
    let message = load_error(load_msh(&path), &path);
    assert!(
        message.contains("line 20") && message.contains("node tag 99"),
        "{message}"
    );
    let path = write_text("bad.msh", &text.replace("3 4 2 2 8", "3 4 9 2 8"));
    let message = load_error(load_msh(&path), &path);
    assert!(
        message.contains("line 20") && message.contains("9 tags"),
        "{message}"
    );
}
