//! Volumes of several values per voxel (SH coefficients), with the file builder of the NIfTI
//! tests.

use super::*;

#[test]
fn several_values_per_voxel() {
    // 3x2x2 voxels, 6 values each (order-2 SH), f32, NIfTI order: x fastest, the 4th axis last.
    let mut nii = Nii::new([3, 2, 2], 16);
    nii.dim[0] = 4;
    nii.dim[4] = 6;
    let values: Vec<f32> = (0..72).map(|i| i as f32 * 0.5).collect();
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let path = nii.write_gz("sh.nii.gz", &bytes);
    let v = load_nifti_components(&path).unwrap();
    assert_eq!((v.dims, v.components), ([3, 2, 2], 6));
    // Voxel (1, 1, 0) is number 4 in each 12-value component block.
    assert_eq!(v.voxel(1, 1, 0), vec![2.0, 8.0, 14.0, 20.0, 26.0, 32.0]);
    // The scalar loader refuses it and says how to draw it.
    let (_, text) = load_err(&path);
    assert!(text.contains("dim[4]=6") && text.contains("sh:"), "{text}");
    // Truncated data names the file.
    let short = nii.write("short.nii", &bytes[..100]);
    let err = load_nifti_components(&short).unwrap_err().to_string();
    assert!(err.contains("short.nii"), "{err}");
    // Non-finite values are refused.
    let mut bad = values.clone();
    bad[7] = f32::NAN;
    let bytes: Vec<u8> = bad.iter().flat_map(|v| v.to_le_bytes()).collect();
    let err = load_nifti_components(&nii.write("nan.nii", &bytes))
        .unwrap_err()
        .to_string();
    assert!(err.contains("nan.nii") && err.contains("value 7"), "{err}");
}

#[test]
fn one_voxel_and_one_slice_load() {
    let v = load_nifti_components(&crate::test_files::test_data("sh_one_voxel.nii")).unwrap();
    assert_eq!((v.dims, v.components), ([1, 1, 1], 6));
    assert_eq!(v.voxel(0, 0, 0), vec![1.0, 0.2, -0.1, 0.05, 0.0, 0.3]);

    let v = load_nifti_components(&crate::test_files::test_data("sh_one_slice.nii")).unwrap();
    assert_eq!((v.dims, v.components), ([3, 2, 1], 6));
    assert_eq!(v.voxel(2, 1, 0)[0], 1.0);

    // No voxels at all is still an error, and scalar volumes still need two samples.
    let mut nii = Nii::new([3, 0, 1], 16);
    nii.dim[0] = 4;
    nii.dim[4] = 6;
    let err = load_nifti_components(&nii.write("empty.nii", &[]))
        .unwrap_err()
        .to_string();
    assert!(err.contains("empty.nii") && err.contains("3x0x1"), "{err}");
    let nii = Nii::new([3, 2, 1], 16);
    let (_, text) = load_err(&nii.write("flat.nii", &[0; 24]));
    assert!(text.contains("3x2x1"), "{text}");
}
