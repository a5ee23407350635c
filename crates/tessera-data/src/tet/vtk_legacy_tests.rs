//! Tests of the legacy VTK loader and writer.
use super::*;
use crate::test_files::test_path;
use crate::tet::procedural::sphere_mesh;
use crate::tet::tests::{data_file, load_error, two_tets, write_text};

#[test]
fn round_trip() {
    for mesh in [two_tets(), sphere_mesh(3)] {
        let path = test_path("rt.vtk");
        write_vtk_legacy_ascii(&mesh, &path).expect("write");
        let (back, report) = crate::tet::load_tet_mesh(&path).expect("load");
        assert_eq!(report, MeshReport::default());
        assert_eq!(back, mesh);
    }
}

const HEAD: &str = "# vtk DataFile Version 3.0\ntest\nASCII\nDATASET UNSTRUCTURED_GRID\n\
                    POINTS 5 double\n0 0 0 1 0 0\n0 1 0 0 0 1 1 1 1\n";

#[test]
fn mixed_cells_and_attributes() {
    let text = format!(
        "{HEAD}CELLS 3 14\n3 0 1 2\n4 0 1 2 3\n4 4 1 3 2\nCELL_TYPES 3\n5 10 10\n\
         CELL_DATA 3\nSCALARS id int\nLOOKUP_TABLE default\n9 8 7\n\
         VECTORS v float\n0 0 0 1 1 1 2 2 2\n\
         POINT_DATA 5\nFIELD extra 1\nf 2 5 float\n1 2 3 4 5 6 7 8 9 0\n\
         SCALARS vec float 2\nLOOKUP_TABLE default\n0 0 0 0 0 0 0 0 0 0\n\
         SCALARS heat float 1\nLOOKUP_TABLE default\n1 2 3 4 5\n"
    );
    let path = write_text("mixed.vtk", &text);
    let (mesh, report) = load_vtk_legacy(&path).expect("load");
    assert_eq!(report.skipped_cells, 1);
    assert_eq!(mesh.tets, vec![[0, 1, 2, 3], [4, 1, 3, 2]]);
    assert_eq!(mesh.regions, Some(vec![8, 7]));
    assert_eq!(mesh.scalar_name, "heat");
    assert_eq!(mesh.scalars, Some(vec![1.0, 2.0, 3.0, 4.0, 5.0]));
}

#[test]
fn version_5_1_binary() {
    let mut bytes =
        b"# vtk DataFile Version 5.1\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
            .to_vec();
    for v in [0f32, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.] {
        bytes.extend(v.to_be_bytes());
    }
    bytes.extend(b"\nCELLS 3 7\nOFFSETS vtktypeint64\n");
    for o in [0i64, 4, 7] {
        bytes.extend(o.to_be_bytes());
    }
    bytes.extend(b"\nCONNECTIVITY vtktypeint64\n");
    for c in [0i64, 2, 1, 3, 0, 1, 2] {
        bytes.extend(c.to_be_bytes());
    }
    bytes.extend(b"\nCELL_TYPES 2\n");
    for t in [10i32, 5] {
        bytes.extend(t.to_be_bytes());
    }
    bytes.extend(b"\nPOINT_DATA 4\nSCALARS s double\nLOOKUP_TABLE default\n");
    for s in [1f64, -1.0, 0.5, 2.0] {
        bytes.extend(s.to_be_bytes());
    }
    bytes.extend(b"\nMETADATA\nINFORMATION 0\n\n");
    let path = test_path("bin.vtk");
    std::fs::write(&path, bytes).expect("write");
    let (mesh, report) = load_vtk_legacy(&path).expect("load");
    assert_eq!((report.reoriented, report.skipped_cells), (1, 1));
    assert_eq!(mesh.tets, vec![[0, 2, 3, 1]]);
    assert_eq!(mesh.vertices[3], [0.0, 0.0, 1.0]);
    assert_eq!(mesh.scalars, Some(vec![1.0, -1.0, 0.5, 2.0]));
}

#[test]
fn bad_files() {
    let cells = "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n";
    let cases = [
        (format!("{HEAD}CELLS 1 5\n4 0 1 2\n9\nCELL_TYPES 1\n10\n"), "line 9", "out of range"),
        (format!("{HEAD}CELLS 1 5\n4 0 1 2"), "line 9", "file ends early"),
        (format!("{HEAD}CELLS 2 10\n4 0 1 2 3\n4 0 1 2 4\nCELL_TYPES 1\n10\n"), "line 11", "CELL_TYPES has 1"),
        (format!("{HEAD}{cells}POINT_DATA 4\n"), "line 12", "POINT_DATA 4"),
        ("# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0 0 nan 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n".to_string(), "vertex 2", "non-finite"),
        (format!("{HEAD}CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n"), "", "empty mesh"),
        (format!("{HEAD}{cells}BOGUS 3\n"), "line 12", "BOGUS"),
        ("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n".to_string(), "line 4", "UNSTRUCTURED_GRID"),
        ("hello\n".to_string(), "line 1", "not a legacy VTK"),
    ];
    for (text, place, what) in cases {
        let path = write_text("bad.vtk", &text);
        let message = load_error(load_vtk_legacy(&path), &path);
        assert!(
            message.contains(place) && message.contains(what),
            "{message}"
        );
    }
}

#[test]
fn attributes_before_or_after_a_second_geometry_section_are_errors() {
    let path = data_file("cell_data_before_cells.vtk");
    let message = load_error(load_vtk_legacy(&path), &path);
    assert!(
        message.contains("line 7") && message.contains("CELL_DATA comes before CELLS"),
        "{message}"
    );
    let path = data_file("cells_twice.vtk");
    let message = load_error(load_vtk_legacy(&path), &path);
    assert!(
        message.contains("line 15") && message.contains("second CELLS section"),
        "{message}"
    );
    assert!(message.contains("line 7"), "{message}");
}

#[test]
fn field_data_as_meshio_writes_it() {
    let (mesh, report) = load_vtk_legacy(&data_file("field_data.vtk")).expect("load");
    assert_eq!(report.skipped_cells, 1);
    assert_eq!(mesh.tets, vec![[0, 1, 2, 3], [4, 1, 3, 2]]);
    assert_eq!(mesh.scalar_name, "temperature");
    assert_eq!(mesh.scalars, Some(vec![10.5, 11.5, 12.5, 13.5, 14.5]));
    assert_eq!(mesh.regions, Some(vec![4, 5]));
    assert_eq!(
        mesh.absorption,
        Some(vec![[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]])
    );
}

#[test]
fn messages_quote_what_was_found() {
    let path = data_file("unknown_encoding.vtk");
    let message = load_error(load_vtk_legacy(&path), &path);
    assert!(
        message.contains("line 3") && message.contains("found \"HEX\""),
        "{message}"
    );
    assert!(!message.contains("Some("), "{message}");
    let path = write_text(
        "short.vtk",
        "# vtk DataFile Version 3.0\nt\nASCII\nDATASET\n",
    );
    let message = load_error(load_vtk_legacy(&path), &path);
    assert!(
        message.contains("found DATASET the end of the file"),
        "{message}"
    );
    assert!(!message.contains("None"), "{message}");
}

#[test]
fn counts_beyond_the_file_fail_before_allocating() {
    for text in [
        format!("{HEAD}CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 99999999999999\n10\n"),
        "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 999999999999999 float\n0 0 0\n".to_string(),
        "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 9999999999999999999 float\n0 0 0\n".to_string(),
        format!("{HEAD}CELLS 1 99999999999999\n4 0 1 2 3\n"),
        format!("{HEAD}CELLS 1 5\n9999999999999 0 1 2 3\n"),
        format!("{HEAD}CELLS 1 0\n4 0 1 2 3\nCELL_TYPES 1\n10\n"),
    ] {
        let path = write_text("huge.vtk", &text);
        let message = load_error(load_vtk_legacy(&path), &path);
        assert!(
            message.contains("remain")
                || message.contains("too many")
                || message.contains("bytes left")
                || message.contains("runs past"),
            "{message}"
        );
    }
}

/// A mesh of other cells only says so and how to get tetrahedra, not just "empty".
#[test]
fn only_other_cells_is_explained() {
    let text = format!("{HEAD}CELLS 1 9\n8 0 1 2 3 4 0 1 2\nCELL_TYPES 1\n12\n");
    let path = write_text("hex.vtk", &text);
    let err = load_vtk_legacy(&path).expect_err("no tets").to_string();
    assert!(err.contains("hex.vtk"), "{err}");
    assert!(err.contains("all 1 cell(s) are of other types"), "{err}");
    assert!(err.contains("tetrahedralize"), "{err}");
}
