//! Where NIfTI files place their grid: the sform, else the qform (with qfac), else nothing.

use super::*;

/// `a` and `b` agree to within float rounding.
fn close(a: [[f32; 3]; 3], b: [[f32; 3]; 3]) -> bool {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .all(|(x, y)| (x - y).abs() < 1e-6)
}

#[test]
fn sform_places_the_grid() {
    for (version, big) in [(1, false), (2, true)] {
        // A grid turned so that i runs towards the feet (spacing 2), j to the right and k
        // to the front, at (10, -20, 30).
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.version = version;
        nii.big = big;
        nii.sform_code = 2;
        nii.srow = [
            [0.0, 1.5, 0.0, 10.0],
            [0.0, 0.0, 3.0, -20.0],
            [-2.0, 0.0, 0.0, 30.0],
        ];
        // A qform is there too; the sform wins.
        nii.qform_code = 1;
        let v = load(&nii.write("sform.nii", &[0; 8]));
        let o = v.orientation();
        assert_eq!(o.source(), OrientationSource::NiftiSform, "NIfTI-{version}");
        assert_eq!(o.space(), Some(AnatomicalSpace::Ras));
        assert_eq!(o.origin(), [10.0, -20.0, 30.0]);
        let want = [[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert!(close(o.direction(), want), "{:?}", o.direction());
        assert_eq!(v.up_axis(), Some((0, -1)));
    }
}

#[test]
fn qform_with_negative_qfac() {
    // A quarter turn about x (a = b = sqrt(1/2)) takes j to +z and k to -y; qfac -1 then
    // reverses k, to +y.
    let half = std::f64::consts::FRAC_1_SQRT_2;
    for version in [1, 2] {
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.version = version;
        nii.qform_code = 1;
        nii.quatern = [half, 0.0, 0.0];
        nii.qoffset = [-1.0, 2.0, -3.0];
        nii.pixdim[0] = -1.0;
        let v = load(&nii.write_gz("qform.nii.gz", &[0; 8]));
        let o = v.orientation();
        assert_eq!(o.source(), OrientationSource::NiftiQform, "NIfTI-{version}");
        assert_eq!(o.origin(), [-1.0, 2.0, -3.0]);
        let want = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]];
        assert!(close(o.direction(), want), "{:?}", o.direction());
        assert_eq!(v.up_axis(), Some((1, 1)));
        // The spacing stays pixdim's.
        assert_eq!(v.spacing(), [1.0; 3]);
    }
    // The identity quaternion with qfac -1: slices stacked downwards.
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.qform_code = 1;
    nii.pixdim[0] = -1.0;
    let v = load(&nii.write("flip.nii", &[0; 8]));
    assert_eq!(v.up_axis(), Some((2, -1)));
}

#[test]
fn no_usable_placement_means_the_default() {
    let nii = Nii::new([2, 2, 2], 2);
    let v = load(&nii.write("plain.nii", &[0; 8]));
    assert_eq!(v.orientation().source(), OrientationSource::Default);
    assert_eq!(v.orientation().unusable(), None);
    assert_eq!(v.up_axis(), None);

    // An sform of zeros is skipped for the qform, and the skip is recorded.
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.sform_code = 1;
    nii.qform_code = 1;
    let v = load(&nii.write("zeros.nii", &[0; 8]));
    assert_eq!(v.orientation().source(), OrientationSource::NiftiQform);
    assert_eq!(
        v.orientation().unusable(),
        Some(OrientationSource::NiftiSform)
    );
    assert_eq!(v.up_axis(), Some((2, 1)));

    // A qform alone that cannot be used (a NaN offset) leaves the default, recorded too.
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.qform_code = 1;
    nii.qoffset = [f64::NAN, 0.0, 0.0];
    let v = load(&nii.write("nan.nii", &[0; 8]));
    assert_eq!(v.orientation().source(), OrientationSource::Default);
    assert_eq!(
        v.orientation().unusable(),
        Some(OrientationSource::NiftiQform)
    );
}
