use std::path::Path;

use glam::Vec3;

use crate::marching_cubes::{marching_cubes_with, AmbiguityRule};
use crate::mesh::{MeshFormat, TriangleMesh};
use crate::mesh_read::{read_mesh_file, read_obj, read_ply};
use crate::procedural::{generate, ProceduralKind};
use crate::volume::ScalarType;

fn surface() -> TriangleMesh {
    let volume = generate(ProceduralKind::Sphere, 12, ScalarType::F32).unwrap();
    marching_cubes_with(&volume, 0.6123, AmbiguityRule::AsymptoticDecider)
}

#[test]
fn ply_and_obj_exports_read_back_bit_for_bit() {
    let mesh = surface();
    assert!(mesh.triangle_count() > 50);
    for format in [MeshFormat::Ply, MeshFormat::Obj] {
        let mut bytes = Vec::new();
        mesh.write_as(format, &mut bytes).unwrap();
        let read = match format {
            MeshFormat::Ply => read_ply(&bytes),
            MeshFormat::Obj => read_obj(&String::from_utf8(bytes).unwrap()),
        }
        .unwrap();
        assert_eq!(read, mesh, "{format:?}");
    }
}

#[test]
fn the_extension_picks_the_format_and_others_are_refused() {
    assert_eq!(
        MeshFormat::from_path(Path::new("a.PLY")).unwrap(),
        MeshFormat::Ply
    );
    assert_eq!(
        MeshFormat::from_path(Path::new("b/c.obj")).unwrap(),
        MeshFormat::Obj
    );
    let e = MeshFormat::from_path(Path::new("mesh.stl"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("mesh.stl") && e.contains(".ply or .obj"), "{e}");
    let e = read_mesh_file(Path::new("/nonexistent/m.ply"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/m.ply"), "{e}");
}

#[test]
fn other_tools_ascii_ply_and_obj_with_texture_indices_are_read() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let mesh = read_ply(ply.as_bytes()).unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    assert_eq!(mesh.positions[1], Vec3::X);
    assert!(mesh.normals.is_empty());
    let obj = "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 -1/1\n";
    let mesh = read_obj(obj).unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
}

#[test]
fn broken_meshes_say_what_is_wrong() {
    let cases: [(&str, &str); 5] = [
        ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", "'y'"),
        (
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
             property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
             end_header\n0 0 0\n3 0 0 5\n",
            "index 5 of 1 vertices",
        ),
        (
            "ply\nformat binary_big_endian 1.0\nend_header\n",
            "binary_big_endian",
        ),
        ("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", "ends inside"),
        ("no header at all", "end_header"),
    ];
    for (text, expected) in cases {
        let e = read_ply(text.as_bytes()).unwrap_err();
        assert!(e.contains(expected), "{e} (wanted {expected})");
    }
    let e = read_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\n").unwrap_err();
    assert!(e.contains("line 5") && e.contains("4 corners"), "{e}");
    let e = read_obj("v 0 0 0\nf 1 2 3\n").unwrap_err();
    assert!(e.contains("index 2 of 1"), "{e}");
    let e = read_obj("v 0 zero 0\n").unwrap_err();
    assert!(e.contains("line 1"), "{e}");
}
