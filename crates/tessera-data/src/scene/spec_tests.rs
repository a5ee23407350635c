//! Tests of `spec`: which loader a spec goes to, volume and tet-mesh specs, their errors.

use super::*;
use crate::test_files::test_path;
use crate::tet::{write_vtu_ascii, MeshReport};

#[test]
fn kinds_of_specs() {
    let cases = [
        ("param:heart", DataKind::Param),
        ("param:anything", DataKind::Param),
        ("sh:fit.nii.gz:z3", DataKind::Param),
        ("procedural:sh-glyphs:4x4:order8", DataKind::Param),
        ("surfaces/Torus.GLSL", DataKind::Param),
        ("tets:box:4", DataKind::Tets),
        ("tets:nonsense", DataKind::Tets),
        ("mesh.vtu", DataKind::Tets),
        ("dir/mesh.VTK", DataKind::Tets),
        ("mesh.node", DataKind::Tets),
        ("mesh.ele", DataKind::Tets),
        ("mesh.msh", DataKind::Tets),
        ("procedural:sphere:64", DataKind::Volume),
        ("procedural:sh-glyph:order4", DataKind::Volume),
        ("bonsai_256x256x256_uint8.raw", DataKind::Volume),
        ("head.nrrd", DataKind::Volume),
        ("scan.nii.gz", DataKind::Volume),
        ("mesh.vtu.gz", DataKind::Volume),
        ("no-extension", DataKind::Volume),
    ];
    for (spec, kind) in cases {
        assert_eq!(DataKind::of_spec(spec), kind, "{spec}");
    }
}

#[test]
fn procedural_volumes() {
    let v = load_volume_spec("procedural:sphere:8:uint16", &RawOptions::default()).unwrap();
    assert_eq!((v.dims(), v.scalar_type().name()), ([8; 3], "uint16"));
    for (spec, expected) in [
        ("procedural:nope:8", "unknown procedural volume 'nope'"),
        ("procedural:sphere", "expected NAME:SIZE"),
        ("procedural:sphere:1", "procedural sphere"),
    ] {
        let err = load_volume_spec(spec, &RawOptions::default())
            .unwrap_err()
            .to_string();
        let label = format!("procedural data '{spec}': ");
        assert!(err.starts_with(&label) && err.contains(expected), "{err}");
    }
}

#[test]
fn volume_files_name_the_file() {
    let missing = test_path("gone_4x4x4_uint8.raw");
    let err = load_volume_spec(missing.to_str().unwrap(), &RawOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("gone_4x4x4_uint8.raw"), "{err}");
    // An extension nobody knows is read as raw data, which needs its shape.
    let odd = test_path("data.xyz");
    std::fs::write(&odd, [0u8; 8]).unwrap();
    let err = load_volume_spec(odd.to_str().unwrap(), &RawOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("data.xyz") && err.contains("--dims"), "{err}");
    let ok = test_path("cube_2x2x2_uint8.raw");
    std::fs::write(&ok, [7u8; 8]).unwrap();
    let v = load_volume_spec(ok.to_str().unwrap(), &RawOptions::default()).unwrap();
    assert_eq!(v.dims(), [2; 3]);
}

#[test]
fn expected_bytes() {
    let raw = RawOptions::default();
    let bytes = |spec: &str, raw: &RawOptions| expected_volume_bytes(spec, raw);
    assert_eq!(
        bytes("procedural:head:64:uint16", &raw),
        Some(64 * 64 * 64 * 2)
    );
    assert_eq!(bytes("procedural:head:64", &raw), Some(64 * 64 * 64));
    assert_eq!(bytes("d/bonsai_256x256x256_uint8.raw", &raw), Some(1 << 24));
    assert_eq!(bytes("v_10x10x10_uint16.raw", &raw), Some(2000));
    // Other types are widened to f32.
    assert_eq!(bytes("v_10x10x10_int8.raw", &raw), Some(4000));
    assert_eq!(bytes("v_10x10x10_float64.raw", &raw), Some(4000));
    // Sizes past u64 saturate rather than overflow.
    let huge = "v_4294967295x4294967295x4294967295_float32.raw";
    assert_eq!(bytes(huge, &raw), Some(u64::MAX));
    assert_eq!(bytes("procedural:head:4294967295", &raw), Some(u64::MAX));
    let told = RawOptions {
        dims: Some([3, 4, 5]),
        dtype: Some("uint16".into()),
        ..RawOptions::default()
    };
    assert_eq!(bytes("v_10x10x10_uint8.raw", &told), Some(120));
    assert_eq!(bytes("plain.raw", &raw), None);
    assert_eq!(bytes("v_10x10x10_complex.raw", &raw), None);
    assert_eq!(bytes("procedural:nope:64", &raw), None);
    // Not volumes, even with a shape given.
    for spec in [
        "tets:box:4",
        "param:heart",
        "procedural:sh-glyphs:2x2:order4",
    ] {
        assert_eq!(bytes(spec, &told), None, "{spec}");
    }
}

#[test]
fn procedural_meshes() {
    let b = TetData::load("tets:box:2").unwrap();
    assert_eq!(
        (b.mesh.tets.len(), b.asteroids, b.report),
        (48, false, None)
    );
    assert_eq!(b.name, "tets:box:2");
    let s = TetData::load("tets:sphere:3").unwrap();
    assert_eq!(
        (s.mesh.tets.len(), s.mesh.scalar_name.as_str()),
        (162, "radius")
    );
    let a = TetData::load("tets:asteroids:7").unwrap();
    assert_eq!((a.mesh.tets.len(), a.asteroids), (7, true));
}

#[test]
fn mesh_spec_errors() {
    let cases = [
        (
            "tets:box",
            "expected tets:box:N, tets:sphere:N, tets:ring:N or tets:asteroids:COUNT",
        ),
        ("tets:box:0", "N must be a whole number from 1 to 200"),
        ("tets:sphere:201", "N must be a whole number from 1 to 200"),
        ("tets:box:two", "N must be a whole number from 1 to 200"),
        (
            "tets:cone:3",
            "unknown mesh 'cone' (box, sphere, ring, asteroids)",
        ),
        ("tets:asteroids:0", "COUNT must be from 1 to 4000000"),
        ("tets:asteroids:4000001", "COUNT must be from 1 to 4000000"),
    ];
    for (spec, expected) in cases {
        let err = TetData::load(spec).unwrap_err().to_string();
        assert_eq!(err, format!("'{spec}': {expected}"));
    }
    let ring = TetData::load("tets:ring:2").unwrap_err().to_string();
    assert!(
        ring.contains("'tets:ring:2'") && ring.contains("at least 3"),
        "{ring}"
    );
    assert!(TetData::load("tets:ring:3").is_ok());
}

#[test]
fn mesh_files() {
    let path = test_path("cube.vtu");
    write_vtu_ascii(&crate::tet::procedural::box_mesh(1), &path).unwrap();
    let spec = path.to_str().unwrap();
    let t = TetData::load(spec).unwrap();
    assert_eq!((t.mesh.tets.len(), t.asteroids), (6, false));
    assert_eq!(t.report, Some(MeshReport::default()));
    assert_eq!(t.repairs(), None);

    let missing = test_path("gone.msh");
    let err = TetData::load(missing.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(err.contains("gone.msh"), "{err}");
    let obj = test_path("shape.obj");
    std::fs::write(&obj, "v 0 0 0\n").unwrap();
    let err = TetData::load(obj.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("shape.obj")
            && err.contains("extension 'obj' is none of")
            && err.contains("does not start like any of them"),
        "{err}"
    );
}

#[test]
fn repairs_are_reported() {
    let mut t = TetData::load("tets:box:1").unwrap();
    assert_eq!(t.repairs(), None);
    t.report = Some(MeshReport {
        reoriented: 2,
        skipped_cells: 5,
        ..MeshReport::default()
    });
    assert_eq!(
        t.repairs().unwrap(),
        "tets:box:1: 2 inverted tets reoriented, 0 degenerate, 5 non-tet cells skipped"
    );
}
