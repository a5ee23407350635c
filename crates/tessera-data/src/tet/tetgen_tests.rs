//! Tests of the TetGen loader and writer.
use super::*;
use crate::test_files::test_path;
use crate::tet::procedural::box_mesh;
use crate::tet::tests::{load_error, two_tets, write_text};

#[test]
fn round_trip() {
    let mesh = two_tets();
    let path = test_path("m.node");
    write_tetgen(&mesh, &path).expect("write");
    for p in [path.clone(), path.with_extension("ele")] {
        let (back, report) = crate::tet::load_tet_mesh(&p).expect("load");
        assert_eq!(report, MeshReport::default());
        assert_eq!(back.vertices, mesh.vertices);
        assert_eq!(back.tets, mesh.tets);
        assert_eq!(back.scalars, mesh.scalars);
        assert_eq!(back.regions, mesh.regions);
    }
    let big = box_mesh(3);
    write_tetgen(&big, &path).expect("write");
    let (back, _) = load_tetgen(&path).expect("load");
    assert_eq!((back.vertices, back.tets), (big.vertices, big.tets));
}

fn pair(node: &str, ele: &str) -> std::path::PathBuf {
    let path = write_text("t.node", node);
    std::fs::write(path.with_extension("ele"), ele).expect("write ele");
    path
}

const NODE0: &str = "# zero based\n4 3 0 0\n0 0 0 0\n1 1 0 0 # comment\n\n2 0 1 0\n3 0 0 1\n";

#[test]
fn zero_based_and_inverted() {
    let path = pair(NODE0, "1 4 1\n0 0 2 1 3 5\n");
    let (mesh, report) = load_tetgen(&path).expect("load");
    assert_eq!(report.reoriented, 1);
    assert_eq!(mesh.regions, Some(vec![5]));
    assert!(mesh.volume_of(0) > 0.0);
    assert!(mesh.scalars.is_none());
    // Non-integral attributes are not regions.
    let path = pair(NODE0, "1 4 1\n0 0 1 2 3 -0.5\n");
    assert_eq!(load_tetgen(&path).expect("load").0.regions, None);
}

#[test]
fn bad_files() {
    let cases = [
        (
            NODE0,
            "1 4 0\n0 0 1 2 4\n",
            "t.ele",
            "line 2",
            "out of range",
        ),
        (NODE0, "2 4 0\n0 0 1 2 3\n", "t.ele", "line", "found 1 of 2"),
        (NODE0, "1 4 0\n0 0 1 2\n", "t.ele", "line 2", "fields"),
        (
            "4 3 0 0\n0 0 0 0\n1 1 0 0\n",
            "1 4 0\n0 0 1 2 3\n",
            "t.node",
            "line",
            "found 2 of 4",
        ),
        (
            "2 3 0 0\n0 0 0 0\n1 nan 0 0\n",
            "1 4 0\n0 0 1 1 1\n",
            "t.ele",
            "vertex 1",
            "non-finite",
        ),
        (
            "1 2 0 0\n0 0 0\n",
            "0 4 0\n",
            "t.node",
            "line 1",
            "dimension",
        ),
        (NODE0, "0 4 0\n", "t.ele", "", "empty mesh"),
        (NODE0, "1 4 0\n0 0 1 x 3\n", "t.ele", "line 2", "\"x\""),
    ];
    for (node, ele, file, place, what) in cases {
        let path = pair(node, ele);
        let text = load_tetgen(&path).expect_err("bad").to_string();
        assert!(
            text.contains(file) && text.contains(place) && text.contains(what),
            "{text}"
        );
    }
    let path = write_text("alone.node", NODE0);
    load_error(load_tetgen(&path), &path.with_extension("ele"));
}

#[test]
fn huge_header_counts_are_errors() {
    let ele = "1 4 0\n1 1 2 3 4\n";
    for (node, what) in [
        (
            "99999999999 3 0 0\n1 0 0 0\n",
            "99999999999 points announced",
        ),
        (
            "1 3 18446744073709551615 1\n1 0 0 0\n",
            "expected 18446744073709551615",
        ),
    ] {
        let path = write_text("huge.node", node);
        std::fs::write(path.with_extension("ele"), ele).expect("write");
        let message = load_error(load_tetgen(&path), &path);
        assert!(
            message.contains("line 1") || message.contains("line 2"),
            "{message}"
        );
        assert!(message.contains(what), "{message}");
    }
    let path = write_text("many.node", "4 3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    std::fs::write(path.with_extension("ele"), "88888888888 4\n1 1 2 3 4\n").expect("write");
    let message = load_error(load_tetgen(&path), &path.with_extension("ele"));
    assert!(
        message.contains("88888888888 tetrahedra announced"),
        "{message}"
    );
}
