//! Tests of `appearance`: the auto integrand, the density and range, the background rule.

use super::*;
use crate::procedural::{generate, ProceduralKind};
use crate::tet::scalar_integral::{normalize_scalar, scalar_range};
use crate::volume::ScalarType;

/// One tet with vertex scalars 0..30, optionally with its own colour.
fn tets(scalars: bool, coloured: bool) -> TetData {
    let mut mesh = TetMesh::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        vec![[0, 1, 2, 3]],
    );
    if scalars {
        mesh.scalars = Some(vec![0.0, 10.0, 20.0, 30.0]);
        mesh.scalar_name = "Temperature".into();
    }
    if coloured {
        mesh.absorption = Some(vec![[0.5, 0.2, 0.1]]);
    }
    TetData {
        name: "one.vtu".into(),
        mesh,
        asteroids: false,
        report: None,
    }
}

fn with(integrand: IntegrandChoice) -> Appearance {
    Appearance {
        integrand,
        ..Appearance::default()
    }
}

fn mode_of(resolved: &ResolvedIntegrand) -> Option<ScalarMode> {
    match resolved {
        ResolvedIntegrand::Scalar { mode, .. } => Some(*mode),
        _ => None,
    }
}

#[test]
fn defaults_are_the_command_lines() {
    let a = Appearance::default();
    assert_eq!(a.iso, IsoValue::Normalized(0.5));
    assert_eq!(a.integrand, IntegrandChoice::Auto);
    assert_eq!(a.transfer, TransferFunction::preset("cool-warm").unwrap());
    assert_eq!(
        (a.density, a.range, a.absorption, a.background),
        (4.0, None, None, None)
    );
}

#[test]
fn iso_texel_is_finite() {
    let volume = generate(ProceduralKind::Sphere, 4, ScalarType::U8).unwrap();
    let a = Appearance::default();
    assert_eq!(a.iso_texel(&volume).unwrap(), volume.iso_to_texel(a.iso));
    let raw = Appearance {
        iso: IsoValue::Raw(17.0),
        ..a.clone()
    };
    assert_eq!(raw.iso_texel(&volume).unwrap(), 17.0);
    let nan = Appearance {
        iso: IsoValue::Raw(f32::NAN),
        ..a
    };
    let err = nan.iso_texel(&volume).unwrap_err().to_string();
    assert_eq!(err, "isovalue NaN is not a finite number");
}

/// Auto integrates scalars by absorption unless the mesh has none or has (or is given)
/// colours of its own; an explicit choice wins; asteroids are always sphere-traced.
#[test]
fn auto_integrand_rule() {
    let auto = Appearance::default();
    let resolve = |a: &Appearance, t: &TetData| mode_of(&a.resolve_integrand(t).unwrap());
    assert_eq!(resolve(&auto, &tets(false, false)), None);
    assert_eq!(
        resolve(&auto, &tets(true, false)),
        Some(ScalarMode::Absorption)
    );
    assert_eq!(resolve(&auto, &tets(true, true)), None);
    let given = Appearance {
        absorption: Some([1.0, 1.0, 0.0]),
        ..Appearance::default()
    };
    assert_eq!(resolve(&given, &tets(true, false)), None);
    let emission = with(IntegrandChoice::Scalar(ScalarMode::Emission));
    assert_eq!(
        resolve(&emission, &tets(true, true)),
        Some(ScalarMode::Emission)
    );
    let tet = with(IntegrandChoice::TetAbsorption);
    assert_eq!(
        tet.resolve_integrand(&tets(true, false)).unwrap(),
        ResolvedIntegrand::TetAbsorption
    );
    let mut field = tets(true, false);
    field.asteroids = true;
    assert_eq!(
        emission.resolve_integrand(&field).unwrap(),
        ResolvedIntegrand::Asteroids
    );
    // The procedural meshes bring colours: auto shows them.
    let sphere = TetData::load("tets:sphere:2").unwrap();
    assert_eq!(resolve(&auto, &sphere), None);
}

#[test]
fn scalar_integrand_table_and_range() {
    let a = Appearance {
        integrand: IntegrandChoice::Scalar(ScalarMode::Maximum),
        transfer: TransferFunction::preset("hot").unwrap(),
        density: 2.5,
        range: Some((10.0, 20.0)),
        ..Appearance::default()
    };
    let resolved = a.resolve_integrand(&tets(true, false)).unwrap();
    let ResolvedIntegrand::Scalar { mode, table, range } = &resolved else {
        panic!("{resolved:?}");
    };
    assert_eq!(*mode, ScalarMode::Maximum);
    assert_eq!(*range, (10.0, 20.0));
    assert_eq!(
        *table,
        IntegrandTable::new(&a.transfer, ScalarMode::Maximum, 2.5, TABLE_KNOTS)
    );
    assert_eq!(
        resolved.describe(&tets(true, false).mesh),
        "maximum of 'temperature'"
    );
    let own = with(IntegrandChoice::Auto).resolve_integrand(&tets(true, false));
    let ResolvedIntegrand::Scalar { range, .. } = own.unwrap() else {
        panic!("auto with scalars integrates them");
    };
    let mesh = &tets(true, false).mesh;
    assert_eq!(range, scalar_range(mesh).unwrap());
    let normalized: Vec<f32> = mesh
        .scalars
        .as_ref()
        .unwrap()
        .iter()
        .map(|&v| normalize_scalar(v, range))
        .collect();
    assert_eq!(normalized, [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]);
}

#[test]
fn scalar_integrand_errors() {
    for density in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let a = Appearance {
            density,
            ..Appearance::default()
        };
        let err = a
            .resolve_integrand(&tets(true, false))
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            format!("--density must be a positive number, not {density}")
        );
        // Tet absorption does not use it.
        assert!(a.resolve_integrand(&tets(false, false)).is_ok());
    }
    let mip = with(IntegrandChoice::Scalar(ScalarMode::Emission));
    let err = mip
        .resolve_integrand(&tets(false, false))
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("one.vtu: ") && err.contains("no per-vertex scalars"),
        "{err}"
    );
}

#[test]
fn descriptions() {
    let mesh = tets(true, false).mesh;
    assert_eq!(
        ResolvedIntegrand::TetAbsorption.describe(&mesh),
        "tet absorption"
    );
    assert_eq!(
        ResolvedIntegrand::Asteroids.describe(&mesh),
        "sphere-traced asteroids"
    );
    let emission = with(IntegrandChoice::Scalar(ScalarMode::Emission));
    let resolved = emission.resolve_integrand(&tets(true, false)).unwrap();
    assert_eq!(resolved.describe(&mesh), "emission of 'temperature'");
}

#[test]
fn background_rule() {
    let a = Appearance::default();
    let scalar = |mode| {
        with(IntegrandChoice::Scalar(mode))
            .resolve_integrand(&tets(true, false))
            .unwrap()
    };
    let tet_bg = |r: &ResolvedIntegrand| a.background(DataKind::Tets, Some(r));
    assert_eq!(tet_bg(&ResolvedIntegrand::TetAbsorption), BACKLIGHT);
    assert_eq!(tet_bg(&scalar(ScalarMode::Absorption)), BACKLIGHT);
    assert_eq!(tet_bg(&scalar(ScalarMode::Emission)), DARK);
    assert_eq!(tet_bg(&scalar(ScalarMode::Maximum)), DARK);
    assert_eq!(tet_bg(&ResolvedIntegrand::Asteroids), DARK);
    assert_eq!(a.background(DataKind::Tets, None), BACKLIGHT);
    assert_eq!(a.background(DataKind::Param, None), [0.1, 0.1, 0.12]);
    assert_eq!(
        a.background(DataKind::Volume, None),
        [20.0 / 255.0, 20.0 / 255.0, 26.0 / 255.0]
    );
    let told = Appearance {
        background: Some([1.0, 0.0, 1.0]),
        ..Appearance::default()
    };
    for kind in [DataKind::Volume, DataKind::Tets, DataKind::Param] {
        let r = ResolvedIntegrand::Asteroids;
        assert_eq!(told.background(kind, Some(&r)), [1.0, 0.0, 1.0]);
    }
}

#[test]
fn one_absorption_colour_for_every_tet() {
    let mut mesh = TetData::load("tets:box:1").unwrap().mesh;
    let own = mesh.absorption.clone();
    Appearance::default().apply_absorption(&mut mesh);
    assert_eq!(mesh.absorption, own);
    let a = Appearance {
        absorption: Some([0.1, 0.2, 0.3]),
        ..Appearance::default()
    };
    a.apply_absorption(&mut mesh);
    assert_eq!(mesh.absorption, Some(vec![[0.1, 0.2, 0.3]; 6]));
}

#[test]
fn integrand_names() {
    let parse = |t| IntegrandChoice::parse(t).unwrap();
    assert_eq!(parse("auto"), IntegrandChoice::Auto);
    assert_eq!(parse("tet-absorption"), IntegrandChoice::TetAbsorption);
    assert_eq!(
        parse("absorption"),
        IntegrandChoice::Scalar(ScalarMode::Absorption)
    );
    assert_eq!(
        parse("emission"),
        IntegrandChoice::Scalar(ScalarMode::Emission)
    );
    assert_eq!(parse("mip"), IntegrandChoice::Scalar(ScalarMode::Maximum));
    let err = IntegrandChoice::parse("glow").unwrap_err().to_string();
    assert!(
        err.contains("'glow'") && err.contains("tet-absorption"),
        "{err}"
    );
}
