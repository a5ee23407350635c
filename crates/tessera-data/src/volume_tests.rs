//! Tests of `Volume`: construction, value ranges, texels, spacing and placement.
use super::*;

fn ramp_u8() -> Volume {
    let v: Vec<u8> = (0..27).map(|i| (i * 9) as u8).collect();
    Volume::new("ramp", [3, 3, 3], [1.0, 2.0, 0.5], Samples::U8(v)).expect("valid")
}

#[test]
fn spacing_can_be_replaced_and_says_what_it_was() {
    let v = ramp_u8();
    assert_eq!(v.replaced_spacing(), None);
    let same = v.clone().with_spacing([1.0, 2.0, 0.5]).expect("same");
    assert_eq!(same.replaced_spacing(), None);
    let v = v.with_spacing([3.0, 3.0, 3.0]).expect("new");
    assert_eq!(v.spacing(), [3.0; 3]);
    assert_eq!(v.replaced_spacing(), Some([1.0, 2.0, 0.5]));
    // A second replacement still names the data's own spacing.
    let v = v.with_spacing([4.0, 4.0, 4.0]).expect("again");
    assert_eq!(v.replaced_spacing(), Some([1.0, 2.0, 0.5]));
    for bad in [[0.0, 1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, f32::NAN]] {
        let err = ramp_u8().with_spacing(bad).expect_err("bad spacing");
        assert!(err.to_string().contains("ramp"), "{err}");
    }
}

#[test]
fn grid_to_physical_applies_spacing_direction_and_origin() {
    use crate::orientation::OrientationSource;
    let v = ramp_u8();
    let p = v
        .grid_to_physical()
        .transform_point3(glam::Vec3::new(2.0, 1.0, 2.0));
    assert_eq!(p, glam::Vec3::new(2.0, 2.0, 1.0));
    // Grid x along world -y, y along world x, z along z; origin (10, 20, 30).
    let placed = Orientation::new(
        [10.0, 20.0, 30.0],
        [[0.0, -5.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        None,
        OrientationSource::Nrrd,
    )
    .expect("valid");
    let v = v.with_orientation(placed);
    let p = v
        .grid_to_physical()
        .transform_point3(glam::Vec3::new(2.0, 1.0, 2.0));
    assert!(
        (p - glam::Vec3::new(12.0, 18.0, 31.0)).length() < 1e-5,
        "{p}"
    );
}

#[test]
fn isovalue_outside_the_values_is_named() {
    let v = ramp_u8();
    assert_eq!(v.isovalue_warning(100.0), None);
    assert_eq!(v.isovalue_warning(234.0), None);
    for iso in [-300.0, 0.0, 234.5, 1000.0, f32::NAN] {
        let w = v.isovalue_warning(iso).expect("warning");
        assert!(w.contains("ramp") && w.contains("0..234"), "{w}");
    }
}

#[test]
fn scalar_type_names_and_sizes() {
    assert_eq!(ScalarType::U8.name(), "uint8");
    assert_eq!(ScalarType::U16.name(), "uint16");
    assert_eq!(ScalarType::F32.name(), "float32");
    assert_eq!(ScalarType::U16.size_bytes(), 2);
    assert_eq!(ScalarType::from_name("F32"), Some(ScalarType::F32));
    assert_eq!(ScalarType::from_name("int8"), None);
}

#[test]
fn accessors_and_indexing() {
    let v = ramp_u8();
    assert_eq!(v.name(), "ramp");
    assert_eq!(v.dims(), [3, 3, 3]);
    assert_eq!(v.spacing(), [1.0, 2.0, 0.5]);
    assert_eq!(v.scalar_type(), ScalarType::U8);
    assert_eq!(v.sample_count(), 27);
    assert_eq!(v.size_bytes(), 27);
    assert_eq!(v.bytes().len(), 27);
    assert_eq!(v.index(1, 2, 1), 1 + 3 * (2 + 3));
    assert_eq!(v.value_range(), (0.0, 234.0));
    assert_eq!(v.texel(2, 2, 2), 234.0);
    assert_eq!(v.texel(1, 0, 0), 9.0);
    assert_eq!(v.texel_range(), (0.0, 234.0));
}

#[test]
fn orientation_defaults_and_can_be_set() {
    use crate::orientation::{AnatomicalSpace, OrientationSource};
    let v = ramp_u8();
    assert_eq!(v.orientation(), &Orientation::default());
    assert_eq!(v.up_axis(), None);
    let coronal = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]];
    let placed = Orientation::new(
        [1.0, 2.0, 3.0],
        coronal,
        Some(AnatomicalSpace::Ras),
        OrientationSource::NiftiSform,
    )
    .expect("valid");
    let v = v.with_orientation(placed);
    assert_eq!(v.orientation().origin(), [1.0, 2.0, 3.0]);
    assert_eq!(v.up_axis(), Some((1, 1)));
    // The samples are untouched.
    assert_eq!(v.texel(1, 0, 0), 9.0);
}

#[test]
fn texel_space_conversions() {
    let u16s: Vec<u16> = (0..8).map(|i| i * 1000).collect();
    let v = Volume::new("w", [2, 2, 2], [1.0; 3], Samples::U16(u16s)).expect("valid");
    assert_eq!(v.bytes().len(), 16);
    assert_eq!(v.size_bytes(), 16);
    assert_eq!(v.texel(1, 1, 1), 7000.0);
    assert_eq!(v.raw_to_texel(65535.0), 65535.0);
    assert_eq!(v.texel_range(), (0.0, 7000.0));
    // Normalized 0.5 of [0, 7000] is 3500 raw, which is also its texel value.
    assert_eq!(v.iso_to_texel(IsoValue::Normalized(0.5)), 3500.0);
    assert_eq!(v.iso_to_texel(IsoValue::Normalized(0.0)), 0.0);
    assert_eq!(v.iso_to_texel(IsoValue::Normalized(1.0)), 7000.0);
    assert_eq!(v.iso_to_texel(IsoValue::Raw(100.0)), 100.0);

    let full: Vec<u16> = vec![0, 1, 2, 3, 4, 5, 6, 65535];
    let v = Volume::new("full", [2, 2, 2], [1.0; 3], Samples::U16(full)).expect("valid");
    assert_eq!(v.texel(1, 1, 1), 65535.0);
    assert_eq!(v.texel_range(), (0.0, 65535.0));

    let f: Vec<f32> = (0..8).map(|i| i as f32 - 2.0).collect();
    let v = Volume::new("f", [2, 2, 2], [1.0; 3], Samples::F32(f)).expect("valid");
    assert_eq!(v.value_range(), (-2.0, 5.0));
    assert_eq!(v.texel_range(), (-2.0, 5.0));
    assert_eq!(v.iso_to_texel(IsoValue::Normalized(1.0)), 5.0);
    assert_eq!(v.texel(1, 0, 0), -1.0);
}

#[test]
fn rejects_bad_dims_len_and_spacing() {
    let err = Volume::new("thin", [4, 1, 4], [1.0; 3], Samples::U8(vec![0; 16])).unwrap_err();
    assert!(matches!(err, DataError::InvalidDims { .. }), "{err}");
    assert!(err.to_string().contains("thin"));

    let err = Volume::new("short", [2, 2, 2], [1.0; 3], Samples::U8(vec![0; 7])).unwrap_err();
    assert!(matches!(err, DataError::Invalid(_)), "{err}");
    assert!(err.to_string().contains("short"));

    for bad in [0.0, -1.0, f32::NAN] {
        let err = Volume::new("sp", [2, 2, 2], [1.0, bad, 1.0], Samples::U8(vec![0; 8]));
        assert!(matches!(err, Err(DataError::Invalid(_))));
    }
}

#[test]
fn non_finite_rejected_with_first_voxel() {
    let mut f = vec![0.5f32; 4 * 3 * 2];
    f[1 + 4 * (2 + 3)] = f32::NAN; // voxel (1, 2, 1)
    f[23] = f32::INFINITY;
    let err = Volume::new("nanvol", [4, 3, 2], [1.0; 3], Samples::F32(f.clone())).unwrap_err();
    match &err {
        DataError::NonFinite { count, first, .. } => {
            assert_eq!(*count, 2);
            assert_eq!(*first, [1, 2, 1]);
        }
        other => panic!("unexpected {other}"),
    }
    assert!(err.to_string().contains("nanvol"));

    let v = Volume::with_nan_policy(
        "nanvol",
        [4, 3, 2],
        [1.0; 3],
        Samples::F32(f),
        NanPolicy::Replace(-1.0),
    )
    .expect("replaced");
    assert_eq!(v.texel(1, 2, 1), -1.0);
    assert_eq!(v.value_range(), (-1.0, 0.5));

    let err = Volume::with_nan_policy(
        "n",
        [2, 2, 2],
        [1.0; 3],
        Samples::F32(vec![0.0; 8]),
        NanPolicy::Replace(f32::NAN),
    );
    assert!(matches!(err, Err(DataError::Invalid(_))));
}

#[test]
fn default_policy_is_reject() {
    assert_eq!(NanPolicy::default(), NanPolicy::Reject);
}
