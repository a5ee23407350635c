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
