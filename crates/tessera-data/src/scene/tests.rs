//! Tests of `Dataset`: each kind of spec reaches its loader and keeps its name.

use super::*;
use crate::test_files::test_path;

#[test]
fn one_front_door() {
    let options = LoadOptions::default();
    let volume = Dataset::load("procedural:head:4", &options).unwrap();
    assert_eq!(
        (volume.kind(), volume.name()),
        (DataKind::Volume, "head_4x4x4_uint8")
    );
    let tets = Dataset::load("tets:asteroids:3", &options).unwrap();
    assert_eq!(
        (tets.kind(), tets.name()),
        (DataKind::Tets, "tets:asteroids:3")
    );
    assert!(matches!(
        tets,
        Dataset::Tets(TetData {
            asteroids: true,
            ..
        })
    ));
    let param = Dataset::load("param:heart", &options).unwrap();
    assert_eq!(
        (param.kind(), param.name()),
        (DataKind::Param, "param:heart")
    );
    let glyphs = Dataset::load("procedural:sh-glyphs:2x1:order2", &options).unwrap();
    let Dataset::Param(data) = glyphs else {
        panic!("glyphs are parametric");
    };
    assert_eq!(data.scene.objects.len(), 2);

    let path = test_path("ring.glsl");
    let text =
        "// u: 0 tau\n// v: 0 1\nvec3 f(float u, float v) { return vec3(cos(u), sin(u), v); }\n";
    std::fs::write(&path, text).unwrap();
    let Dataset::Param(user) = Dataset::load(path.to_str().unwrap(), &options).unwrap() else {
        panic!("a user function is parametric");
    };
    assert_eq!(user.user.map(|f| f.text), Some(text.to_string()));
}

#[test]
fn errors_come_from_the_right_loader() {
    let options = LoadOptions::default();
    let err = |spec: &str| Dataset::load(spec, &options).unwrap_err().to_string();
    assert!(err("tets:box:0").contains("N must be"));
    assert!(err("param:cube").contains("unknown parametric scene"));
    assert!(err("procedural:cube:8").contains("procedural data 'procedural:cube:8'"));
    let missing = test_path("lost.vtu");
    assert!(err(missing.to_str().unwrap()).contains("lost.vtu"));
    let missing = test_path("lost.nrrd");
    assert!(err(missing.to_str().unwrap()).contains("lost.nrrd"));
}

#[test]
fn files_with_unknown_extensions_are_told_by_their_content() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let options = LoadOptions::default();
    let mesh = data.join("mesh_with_unknown_extension.dat");
    let spec = mesh.to_str().unwrap();
    assert_eq!(DataKind::of_spec(spec), DataKind::Tets);
    let Dataset::Tets(tets) = Dataset::load(spec, &options).expect("mesh") else {
        panic!("a legacy VTK file is a mesh");
    };
    assert_eq!(tets.mesh.tet_count(), 2);

    let image = test_path("image.xml");
    std::fs::copy(data.join("ascii_u8.vti"), &image).unwrap();
    let spec = image.to_str().unwrap();
    assert_eq!(DataKind::of_spec(spec), DataKind::Volume);
    let Dataset::Volume(volume) = Dataset::load(spec, &options).expect("volume") else {
        panic!("image data is a volume");
    };
    assert_eq!(volume.dims(), [3, 2, 2]);

    // A mesh asked for as a volume, and unknown content asked for as a mesh.
    let err = crate::load::load_volume(&mesh, &Default::default()).unwrap_err();
    assert!(
        err.to_string()
            .contains("is a legacy VTK file, which holds a tetrahedral mesh"),
        "{err}"
    );
    let err = crate::tet::load_tet_mesh(&image).unwrap_err();
    assert!(
        err.to_string()
            .contains("the content is VTK XML image data"),
        "{err}"
    );
    let other = test_path("noise.bin");
    std::fs::write(&other, [7u8; 64]).unwrap();
    let err = Dataset::load(other.to_str().unwrap(), &options).unwrap_err();
    assert!(err.to_string().contains("read as a raw volume"), "{err}");
}
