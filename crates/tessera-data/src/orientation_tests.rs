//! Tests of `orientation`.

use super::*;

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

#[test]
fn nrrd_space_names() {
    for (name, space) in [
        ("right-anterior-superior", AnatomicalSpace::Ras),
        ("RAS", AnatomicalSpace::Ras),
        ("RAST", AnatomicalSpace::Ras),
        ("left-anterior-superior", AnatomicalSpace::Las),
        ("Left-Posterior-Superior-Time", AnatomicalSpace::Lps),
        ("lps", AnatomicalSpace::Lps),
    ] {
        assert_eq!(AnatomicalSpace::from_nrrd(name), Some(space), "{name}");
    }
    for name in ["scanner-xyz", "3D-right-handed", "RA", "rasx", ""] {
        assert_eq!(AnatomicalSpace::from_nrrd(name), None, "{name}");
    }
}

#[test]
fn axes_are_normalized_and_bad_ones_refused() {
    let o = Orientation::new(
        [1.0, 2.0, 3.0],
        [[2.0, 0.0, 0.0], [0.0, 0.0, -3.0], [0.0, 0.5, 0.0]],
        None,
        OrientationSource::Nrrd,
    )
    .expect("valid");
    assert_eq!(o.origin(), [1.0, 2.0, 3.0]);
    assert_eq!(
        o.direction(),
        [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]
    );
    assert_eq!(o.source(), OrientationSource::Nrrd);
    let zero_axis = [[1.0, 0.0, 0.0], [0.0; 3], [0.0, 0.0, 1.0]];
    let none = OrientationSource::Default;
    assert!(Orientation::new([0.0; 3], zero_axis, None, none).is_none());
    assert!(Orientation::new([f64::NAN, 0.0, 0.0], IDENTITY, None, none).is_none());
    let inf_axis = [[f64::INFINITY, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(Orientation::new([0.0; 3], inf_axis, None, none).is_none());
}

#[test]
fn up_axis_follows_the_direction_matrix() {
    let ras = Some(AnatomicalSpace::Ras);
    let src = OrientationSource::NiftiSform;
    // Axial slices stacked upwards: grid z is superior.
    let axial = Orientation::new([0.0; 3], IDENTITY, ras, src).expect("valid");
    assert_eq!(axial.up_axis(), Some((2, 1)));
    // Coronal slices stored top-down: grid y runs from head to feet.
    let coronal = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
    let o = Orientation::new([0.0; 3], coronal, ras, src).expect("valid");
    assert_eq!(o.up_axis(), Some((1, -1)));
    // Slightly oblique: the nearest axis wins.
    let oblique = [[0.1, 0.0, 0.99], [1.0, 0.0, -0.1], [0.0, 1.0, 0.0]];
    let o = Orientation::new([0.0; 3], oblique, Some(AnatomicalSpace::Lps), src).unwrap();
    assert_eq!(o.up_axis(), Some((0, 1)));
    // Without an anatomical space nothing says where up is.
    let o = Orientation::new([0.0; 3], IDENTITY, None, src).expect("valid");
    assert_eq!(o.up_axis(), None);
    assert_eq!(Orientation::default().up_axis(), None);
    assert_eq!(Orientation::default().source(), OrientationSource::Default);
}

#[test]
fn an_affine_gives_spacing_origin_and_unit_axes() {
    // small_64D's sform: 2 mm voxels, grid x along world -y, y and z turned about world y.
    let rows = [
        [0.0, -2.0, 0.0, 20.0],
        [-1.9397, 0.0, -0.48723, 25.17],
        [-0.48723, 0.0, 1.9397, 12.32],
    ];
    let (o, spacing) = Orientation::from_affine(rows).expect("a usable affine");
    for (s, want) in spacing.iter().zip([2.0, 2.0, 2.0]) {
        assert!((s - want).abs() < 1e-3, "{spacing:?}");
    }
    assert_eq!(o.origin(), [20.0, 25.17, 12.32]);
    assert_eq!(o.direction()[1], [-1.0, 0.0, 0.0]);
    assert!((o.direction()[0][1] + 0.97).abs() < 0.01);
    assert_eq!(o.space(), Some(AnatomicalSpace::Ras));
    assert_eq!(o.source(), OrientationSource::Affine);
    let mut flat = rows;
    flat[0][1] = 0.0;
    assert!(
        Orientation::from_affine(flat).is_none(),
        "an axis of no length"
    );
    let mut nan = rows;
    nan[2][3] = f64::NAN;
    assert!(
        Orientation::from_affine(nan).is_none(),
        "a value that is not finite"
    );
}
