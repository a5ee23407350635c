//! Tests of `TetMesh`, its validation and topology, plus helpers the format tests share.
use std::collections::HashSet;

use glam::Vec3;

use super::procedural::{box_mesh, sphere_mesh};
use super::*;
use crate::test_files::test_path;

/// A unit corner tet followed by a second tet sharing its face (1, 2, 3).
pub(crate) fn two_tets() -> TetMesh {
    let mut mesh = TetMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
        ],
        vec![[0, 1, 2, 3], [4, 1, 3, 2]],
    );
    mesh.scalars = Some(vec![0.5, 1.25, -2.0, 3.0, 1e-3]);
    mesh.scalar_name = "temperature".into();
    mesh.regions = Some(vec![3, 7]);
    mesh.absorption = Some(vec![[0.1, 0.2, 0.3], [0.9, 0.8, 0.7]]);
    mesh
}

/// Writes `text` to a fresh temp file named `name`.
pub(crate) fn write_text(name: &str, text: &str) -> std::path::PathBuf {
    let path = test_path(name);
    std::fs::write(&path, text).expect("write test file");
    path
}

/// A test input file kept in the crate (`tests/data/NAME`).
pub(crate) fn data_file(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The error message of a failed load, checked to name the file.
pub(crate) fn load_error(result: Result<(TetMesh, MeshReport)>, path: &Path) -> String {
    let text = result.expect_err("load should fail").to_string();
    let name = path.file_name().and_then(|n| n.to_str()).expect("name");
    assert!(text.contains(name), "error does not name {name}: {text}");
    text
}

#[test]
fn counts_bounds_and_volume() {
    let mesh = two_tets();
    assert_eq!((mesh.vertex_count(), mesh.tet_count()), (5, 2));
    let (lo, hi) = mesh.bounds().expect("bounds");
    assert_eq!((lo, hi), (Vec3::ZERO, Vec3::ONE));
    assert!((mesh.volume_of(0) - 1.0 / 6.0).abs() < 1e-12);
    assert!(mesh.volume_of(1) > 0.0);
    assert!(TetMesh::default().bounds().is_none());
}

#[test]
fn validate_rejects_bad_meshes() {
    let err = TetMesh::new(vec![[0.0; 3]], vec![])
        .validate("e.vtk")
        .expect_err("empty");
    assert!(
        err.to_string().contains("e.vtk") && err.to_string().contains("empty"),
        "{err}"
    );

    let mut mesh = two_tets();
    mesh.vertices[4][1] = f32::NAN;
    let text = mesh.validate("nan.msh").expect_err("nan").to_string();
    assert!(
        text.contains("nan.msh") && text.contains("vertex 4"),
        "{text}"
    );

    let mut mesh = two_tets();
    mesh.tets[1][2] = 5;
    let text = mesh.validate("idx.ele").expect_err("index").to_string();
    assert!(
        text.contains("idx.ele") && text.contains("tet 1") && text.contains("5"),
        "{text}"
    );

    let mut mesh = two_tets();
    mesh.regions = Some(vec![1]);
    let text = mesh.validate("r").expect_err("regions").to_string();
    assert!(text.contains("regions"), "{text}");
}

#[test]
fn validate_reorients_and_reports_degenerate() {
    let mut mesh = two_tets();
    mesh.tets[1].swap(0, 1);
    assert!(mesh.volume_of(1) < 0.0);
    let report = mesh.validate("m").expect("valid");
    assert_eq!(report.reoriented, 1);
    assert_eq!(report.degenerate, 0);
    assert!(mesh.volume_of(1) > 0.0);

    let mut mesh = two_tets();
    mesh.vertices.push([0.5, 0.5, 0.0]);
    mesh.tets.push([0, 1, 2, 5]); // flat: all in z = 0
    mesh.regions = None;
    mesh.absorption = None;
    mesh.scalars = None;
    let report = mesh.validate("m").expect("kept");
    assert_eq!((report.degenerate, report.first_degenerate), (1, Some(2)));
    assert_eq!(mesh.tet_count(), 3);
}

#[test]
fn neighbours_of_two_tets() {
    let mesh = two_tets();
    let nb = mesh.neighbours();
    assert_eq!(nb[0], [1, NO_NEIGHBOUR, NO_NEIGHBOUR, NO_NEIGHBOUR]);
    assert_eq!(nb[1], [0, NO_NEIGHBOUR, NO_NEIGHBOUR, NO_NEIGHBOUR]);
    assert_eq!(mesh.boundary_faces().len(), 6);
}

use super::topology::NO_NEIGHBOUR;

/// Checks neighbour symmetry, the boundary count and orientation, and Euler's formula for
/// a mesh of a ball (V - E + F - T = 1).
fn check_topology(mesh: &TetMesh, expected_boundary: Option<usize>) {
    let nb = mesh.neighbours();
    let mut open = 0;
    for (t, faces) in nb.iter().enumerate() {
        for &u in faces {
            if u == NO_NEIGHBOUR {
                open += 1;
            } else {
                let back = nb[u as usize].iter().filter(|&&x| x as usize == t).count();
                assert_eq!(back, 1, "tet {t} and {u} do not link back exactly once");
            }
        }
    }
    let boundary = mesh.boundary_faces();
    assert_eq!(boundary.len(), open);
    if let Some(expected) = expected_boundary {
        assert_eq!(boundary.len(), expected);
    }
    let mut area_sum = Vec3::ZERO;
    for f in &boundary {
        let [a, b, c] = f.map(|v| Vec3::from(mesh.vertices[v as usize]));
        let normal = (b - a).cross(c - a);
        area_sum += normal;
        // Convex meshes centred on the origin: normals point away from it.
        assert!(normal.dot(a + b + c) > 0.0, "face {f:?} points inwards");
    }
    assert!(area_sum.length() < 1e-3, "boundary not closed: {area_sum}");

    let mut edges = HashSet::new();
    for t in &mesh.tets {
        for i in 0..4 {
            for j in i + 1..4 {
                edges.insert((t[i].min(t[j]), t[i].max(t[j])));
            }
        }
    }
    let faces = (4 * mesh.tet_count() + boundary.len()) / 2;
    let euler =
        mesh.vertex_count() as i64 - edges.len() as i64 + faces as i64 - mesh.tet_count() as i64;
    assert_eq!(euler, 1);
}

#[test]
fn box_and_sphere_topology() {
    for n in [1u32, 2, 3, 5] {
        let mesh = box_mesh(n);
        let n = n as usize;
        check_topology(&mesh, Some(2 * 6 * n * n));
        let interior = mesh
            .neighbours()
            .iter()
            .flatten()
            .filter(|&&u| u != NO_NEIGHBOUR)
            .count();
        assert_eq!(interior % 2, 0);
    }
    check_topology(&sphere_mesh(6), Some(2 * 6 * 36));
}

#[test]
fn dispatch_by_extension() {
    let path = write_text("m.obj", "v 0 0 0\n");
    let text = load_error(load_tet_mesh(&path), &path);
    assert!(text.contains("extension"), "{text}");
}

/// Files meshio 5.3 wrote (binary; its ASCII `$NodeData` writer is broken under NumPy 2):
/// two tets with a temperature per point, and a triangle in all but the 4.1 file.
#[test]
fn files_written_by_meshio() {
    for (name, regions, skipped) in [
        ("meshio_gmsh22_binary.msh", [7, 8], 1),
        ("meshio_gmsh41_binary.msh", [7, 7], 0),
        ("meshio_binary.vtk", [2, 2], 1),
        ("meshio_binary.vtu", [2, 2], 1),
    ] {
        let (mesh, report) = load_tet_mesh(&data_file(name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(mesh.tets, vec![[0, 1, 2, 3], [4, 1, 3, 2]], "{name}");
        assert_eq!(mesh.regions, Some(regions.to_vec()), "{name}");
        assert_eq!(mesh.scalar_name, "temperature", "{name}");
        assert_eq!(mesh.scalars, Some(vec![1.0, 2.0, 3.0, 4.0, 5.0]), "{name}");
        assert_eq!(report.skipped_cells, skipped, "{name}");
    }
}

#[test]
fn byte_entries_match_the_path_loaders() {
    use crate::test_files::test_data;
    let cases: [(&str, LoadPath, ParseBytes); 3] = [
        ("meshio_binary.vtu", load_vtu, vtu::parse_bytes),
        (
            "meshio_binary.vtk",
            load_vtk_legacy,
            vtk_legacy::parse_bytes,
        ),
        ("gmsh41_binary.msh", load_msh, gmsh::parse_bytes),
    ];
    for (name, load, parse) in cases {
        let path = test_data(name);
        let bytes = std::fs::read(&path).expect("test file");
        let from_path = load(&path).expect(name);
        assert_eq!(parse(&bytes, &path).expect(name), from_path, "{name}");
        let err = parse(&bytes[..bytes.len() / 2], &path).expect_err("truncated");
        assert!(err.to_string().contains(name), "{err}");
    }

    let mesh = two_tets();
    let path = test_path("pair.node");
    write_tetgen(&mesh, &path).expect("write");
    let (node, ele) = (path.with_extension("node"), path.with_extension("ele"));
    let read = |p: &Path| std::fs::read(p).expect("tetgen file");
    let parsed = tetgen::parse_bytes(&read(&node), &node, &read(&ele), &ele).expect("parse");
    assert_eq!(parsed, load_tetgen(&path).expect("load"));
    let err = tetgen::parse_bytes(&read(&node), &node, b"1 4\n", &ele).expect_err("short .ele");
    assert!(err.to_string().contains("pair.ele"), "{err}");
}

type LoadPath = fn(&Path) -> Result<(TetMesh, MeshReport)>;
type ParseBytes = fn(&[u8], &Path) -> Result<(TetMesh, MeshReport)>;

#[test]
fn cell_values_become_the_mean_of_the_tets_around_each_vertex() {
    let mut mesh = two_tets();
    // A sixth vertex no tet uses.
    mesh.vertices.push([5.0, 5.0, 5.0]);
    let points = mesh.point_values_from_cells(&[2.0, 5.0]).expect("averaged");
    // Vertex 0 only in tet 0, vertex 4 only in tet 1, vertices 1 to 3 in both.
    assert_eq!(&points[..5], &[2.0, 3.5, 3.5, 3.5, 5.0]);
    assert!(points[5].is_nan(), "an unused vertex has no value");
    // Unweighted: the second tet's volume does not move the shared vertices.
    assert!((mesh.volume_of(0).abs() - mesh.volume_of(1).abs()).abs() > 1e-3);
    let nan = mesh
        .point_values_from_cells(&[f32::NAN, 1.0])
        .expect("kept");
    assert!(nan[0].is_nan() && nan[1].is_nan() && nan[4] == 1.0);
    let err = mesh.point_values_from_cells(&[1.0]).expect_err("one short");
    assert_eq!(err.to_string(), "1 cell values for 2 tets");
    mesh.tets[1][0] = 9;
    let err = mesh
        .point_values_from_cells(&[1.0, 2.0])
        .expect_err("bad index");
    assert!(err.to_string().contains("tet 1: vertex index 9"), "{err}");
}
