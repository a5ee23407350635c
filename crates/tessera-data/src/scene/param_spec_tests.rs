//! Tests of `param_spec`: every parametric spec form, the glyph placement, their errors.

use super::*;
use crate::test_files::test_path;

const BASIS: ShBasis = ShBasis::Tournier07 { legacy: false };

fn scene(spec: &str) -> ParamScene {
    named_scene(spec, BASIS).unwrap_or_else(|e| panic!("{spec}: {e}"))
}

fn error(spec: &str) -> String {
    named_scene(spec, BASIS).unwrap_err().to_string()
}

fn glyph_basis(object: &ParamObject) -> ShBasis {
    match &object.function {
        ParamFunction::ShGlyph(g) => g.basis(),
        other => panic!("not a glyph: {other:?}"),
    }
}

#[test]
fn named_surfaces_and_curtains() {
    assert_eq!(
        scene("param:sphere").objects[0].function,
        ParamFunction::Sphere
    );
    assert_eq!(
        scene("param:heart").objects[0].function,
        ParamFunction::Heart
    );
    let shell = scene("param:seashell");
    assert!(matches!(
        shell.objects[..],
        [ParamObject {
            function: ParamFunction::Seashell(_),
            ..
        }]
    ));
    assert_eq!(scene("param:yarn:2x3").objects.len(), 6);
    assert_eq!(scene("param:yarn:2x3:fibres").objects.len(), 36);
}

#[test]
fn glyph_grids() {
    let one = scene("param:sh-glyph:order4");
    assert_eq!(one.objects.len(), 1);
    assert_eq!(one.objects[0].object_to_world, Mat4::IDENTITY);
    assert_eq!(glyph_basis(&one.objects[0]), BASIS);

    // 3x2 glyphs one unit apart, centred, shrunk into the unit square: spacing 1/3, each
    // glyph 0.45 of it.
    let grid = scene("param:sh-glyphs:3x2:order2");
    assert_eq!(grid.objects.len(), 6);
    let spacing = 1.0 / 3.0;
    let m = grid.objects[0].object_to_world;
    let expected = Mat4::from_translation(Vec3::new(-1.0, -0.5, 0.0) * spacing)
        * Mat4::from_scale(Vec3::splat(0.45 * spacing));
    assert!(m.abs_diff_eq(expected, 1e-6), "{m}");
    let (centre, _) = grid.objects[5].bounding_sphere();
    assert!(centre.abs_diff_eq(Vec3::new(1.0, 0.5, 0.0) * spacing, 1e-6));
    assert!(grid.objects.iter().all(|o| glyph_basis(o) == BASIS));
    // The same field under its procedural name.
    assert_eq!(scene("procedural:sh-glyphs:3x2:order2"), grid);
}

#[test]
fn scene_errors_name_the_spec() {
    let cases = [
        (
            "param:cube",
            "'param:cube': unknown parametric scene (param:sphere,",
        ),
        (
            "param:yarn:2x3:wool",
            "'param:yarn:2x3:wool': unknown parametric scene",
        ),
        (
            "param:yarn:2by3",
            "'param:yarn:2by3': expected ROWSxLOOPS, found '2by3'",
        ),
        (
            "param:yarn:0x3",
            "param:yarn:0x3: a curtain of 0 rows of 3 loops needs 1 to",
        ),
        (
            "param:sh-glyph:8",
            "'param:sh-glyph:8': expected orderN (even N, 2 to 16), found '8'",
        ),
        (
            "param:sh-glyph:order3",
            "'param:sh-glyph:order3': expected orderN (even N, 2 to 16)",
        ),
        (
            "param:sh-glyphs:3:order4",
            "'param:sh-glyphs:3:order4': expected WxH, found '3'",
        ),
        (
            "param:sh-glyphs:0x2:order4",
            "param:sh-glyphs:0x2:order4: a glyph grid of 0x2",
        ),
        ("param:sh-glyphs:2x2:orderx", "found 'orderx'"),
        ("heart", "'heart' is not a parametric scene"),
    ];
    for (spec, expected) in cases {
        let err = error(spec);
        assert!(
            err.starts_with(expected) || err.contains(expected),
            "{spec}: {err}"
        );
    }
}

/// A NIfTI-1 file of `dims` voxels with `values.len() / voxels` f32 values each, stored as
/// NIfTI does: x fastest, the values' axis last; spacing 1, no placement.
fn coefficient_file(name: &str, dims: [i16; 3], values: &[f32]) -> std::path::PathBuf {
    placed_coefficient_file(name, dims, values, |_| {})
}

/// [`coefficient_file`] with the 352 header bytes edited by `edit` before writing.
fn placed_coefficient_file(
    name: &str,
    dims: [i16; 3],
    values: &[f32],
    edit: impl FnOnce(&mut [u8]),
) -> std::path::PathBuf {
    let voxels = dims.iter().map(|&d| d as usize).product::<usize>();
    let components = (values.len() / voxels) as i16;
    let mut bytes = vec![0u8; 352];
    bytes[0..4].copy_from_slice(&348i32.to_le_bytes());
    let dim = [4, dims[0], dims[1], dims[2], components, 1, 1, 1];
    for (i, d) in dim.iter().enumerate() {
        bytes[40 + 2 * i..42 + 2 * i].copy_from_slice(&d.to_le_bytes());
    }
    bytes[70..72].copy_from_slice(&16i16.to_le_bytes());
    bytes[72..74].copy_from_slice(&32i16.to_le_bytes());
    for i in 0..8 {
        bytes[76 + 4 * i..80 + 4 * i].copy_from_slice(&1f32.to_le_bytes());
    }
    bytes[108..112].copy_from_slice(&352f32.to_le_bytes());
    bytes[344..348].copy_from_slice(b"n+1\0");
    edit(&mut bytes);
    bytes.extend(values.iter().flat_map(|v| v.to_le_bytes()));
    let path = test_path(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// 2x2x2 voxels of order-2 coefficients; voxels 1 and 4 are all zero and draw nothing.
fn coefficients() -> std::path::PathBuf {
    let mut values = vec![0.0f32; 8 * 6];
    for voxel in [0, 2, 3, 5, 6, 7] {
        values[voxel] = 1.0; // l = 0
        values[3 * 8 + voxel] = 0.1 * voxel as f32; // an l = 2 term
    }
    coefficient_file("fit.nii", [2, 2, 2], &values)
}

#[test]
fn coefficient_files() {
    let path = coefficients();
    let spec = format!("sh:{}", path.display());
    let all = scene(&spec);
    assert_eq!(all.objects.len(), 6);
    // Spacing 1/2 (the longest side has 2 voxels), centred on the volume's middle.
    let (centre, _) = all.objects[0].bounding_sphere();
    assert!(centre.abs_diff_eq(Vec3::splat(-0.25), 1e-6), "{centre}");
    let (centre, _) = all.objects[5].bounding_sphere();
    assert!(centre.abs_diff_eq(Vec3::splat(0.25), 1e-6), "{centre}");
    assert_eq!(scene(&format!("{spec}:z1")).objects.len(), 3);
    let slice = scene(&format!("{spec}:z0"));
    assert_eq!(slice.objects.len(), 3);
    assert_eq!(slice.objects[0], all.objects[0]);

    let err = error(&format!("{spec}:z5"));
    assert!(
        err.starts_with(&format!("{spec}:z5: ")) && err.contains("slice 5"),
        "{err}"
    );
    let missing = test_path("nothing.nii");
    let err = error(&format!("sh:{}", missing.display()));
    assert!(err.contains("nothing.nii"), "{err}");
    // A :z without a number is part of the file name.
    let err = error(&format!("sh:{}:zed", missing.display()));
    assert!(err.contains("nothing.nii:zed"), "{err}");
}

#[test]
fn coefficient_files_are_placed_by_spacing_and_turned_by_orientation() {
    // 2x1x2 voxels of spacing 1 x 1 x 3 whose sform puts grid z from head to feet (world z =
    // -3 k) and grid y anterior.
    let mut values = vec![0.0f32; 4 * 6];
    values[..4].fill(1.0);
    let path = placed_coefficient_file("placed.nii", [2, 1, 2], &values, |header| {
        let put = |header: &mut [u8], at: usize, v: &[f32]| {
            for (i, x) in v.iter().enumerate() {
                header[at + 4 * i..at + 4 * i + 4].copy_from_slice(&x.to_le_bytes());
            }
        };
        put(header, 80, &[1.0, 1.0, 3.0]);
        header[254..256].copy_from_slice(&1i16.to_le_bytes());
        put(header, 280, &[1.0, 0.0, 0.0, 0.0]);
        put(header, 296, &[0.0, 1.0, 0.0, 0.0]);
        put(header, 312, &[0.0, 0.0, -3.0, 0.0]);
    });
    let field = scene(&format!("sh:{}", path.display()));
    assert_eq!(field.objects.len(), 4);
    assert_eq!(field.up, Some(ViewUp::MinusZ));
    // The longest side is z's 2 voxels of 3: 6 units span the unit box.
    let centres: Vec<Vec3> = field
        .objects
        .iter()
        .map(|o| o.bounding_sphere().0)
        .collect();
    let expected = [(-0.5, -1.5), (0.5, -1.5), (-0.5, 1.5), (0.5, 1.5)]
        .map(|(x, z)| Vec3::new(x, 0.0, z) / 6.0);
    for (got, want) in centres.iter().zip(expected) {
        assert!(got.abs_diff_eq(want, 1e-6), "{got} != {want}");
    }
    // Glyphs as wide as the finest side (1) allows, not the coarsest.
    let size = field.objects[0].object_to_world.x_axis.length();
    assert!((size - 0.45 / 6.0).abs() < 1e-6, "{size}");
    // No placement in the file: no view up asked for.
    assert_eq!(scene(&format!("sh:{}", coefficients().display())).up, None);
}

#[test]
fn coefficient_files_of_one_voxel_or_one_slice() {
    let path = crate::test_files::test_data("sh_one_voxel.nii");
    let one = scene(&format!("sh:{}", path.display()));
    assert_eq!(one.objects.len(), 1);
    // The one glyph sits at the middle of the unit box.
    let (centre, _) = one.objects[0].bounding_sphere();
    assert!(centre.abs_diff_eq(Vec3::ZERO, 1e-6), "{centre}");

    let path = crate::test_files::test_data("sh_one_slice.nii");
    let spec = format!("sh:{}", path.display());
    assert_eq!(scene(&spec).objects.len(), 6);
    assert_eq!(scene(&format!("{spec}:z0")).objects.len(), 6);
    let err = error(&format!("{spec}:z1"));
    assert!(err.contains("slice 1") && err.contains("1 slices"), "{err}");
}

#[test]
fn default_basis_follows_the_data() {
    assert_eq!(
        default_basis("sh:fit.nii"),
        ShBasis::Descoteaux07 { legacy: true }
    );
    assert_eq!(
        default_basis("param:sh-glyphs:2x2:order4"),
        ShBasis::Descoteaux07 { legacy: false }
    );
    let spec = format!("sh:{}", coefficients().display());
    let data = ParamData::load(&spec, &LoadOptions::default()).unwrap();
    assert!(data.user.is_none() && data.name == spec);
    assert_eq!(
        glyph_basis(&data.scene.objects[0]),
        ShBasis::Descoteaux07 { legacy: true }
    );
    let told = LoadOptions {
        basis: Some(BASIS),
        ..LoadOptions::default()
    };
    let data = ParamData::load(&spec, &told).unwrap();
    assert_eq!(glyph_basis(&data.scene.objects[0]), BASIS);
    let data = ParamData::load("param:sh-glyph:order2", &LoadOptions::default()).unwrap();
    assert_eq!(
        glyph_basis(&data.scene.objects[0]),
        ShBasis::Descoteaux07 { legacy: false }
    );
}

#[test]
fn user_functions() {
    let path = test_path("wave.glsl");
    std::fs::write(
        &path,
        "// u: 0 1\nvec3 f(float u, float v) { return vec3(u, v, 0.0); }\n",
    )
    .unwrap();
    let spec = path.to_str().unwrap();
    let err = ParamData::load(spec, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("wave.glsl") && err.contains("no range for v"),
        "{err}"
    );
    let options = LoadOptions {
        v_range: Some([-1.0, 2.0]),
        ..LoadOptions::default()
    };
    let data = ParamData::load(spec, &options).unwrap();
    let f = data.user.expect("a user function");
    assert_eq!((f.domain.u, f.domain.v), ([0.0, 1.0], [-1.0, 2.0]));
    assert_eq!(data.scene.objects.len(), 1);
    assert_eq!(
        data.scene.objects[0].function,
        ParamFunction::User(f.domain)
    );
    let missing = test_path("absent.GLSL");
    let err = ParamData::load(missing.to_str().unwrap(), &options)
        .unwrap_err()
        .to_string();
    assert!(err.contains("absent.GLSL"), "{err}");
}

/// Orders no renderer draws are refused while parsing, before any glyph (or its SH tables)
/// is built: order 100 used to build everything first.
#[test]
fn glyph_orders_outside_the_drawable_range_are_refused_at_once() {
    let started = std::time::Instant::now();
    for spec in [
        "param:sh-glyph:order100",
        "param:sh-glyph:order18",
        "param:sh-glyph:order3",
        "param:sh-glyph:order0",
        "param:sh-glyphs:100x100:order100",
    ] {
        let e = error(spec);
        assert!(e.contains(spec) && e.contains("2 to 16"), "{e}");
    }
    assert!(started.elapsed() < std::time::Duration::from_secs(1));
    assert_eq!(scene("param:sh-glyph:order16").objects.len(), 1);
}
