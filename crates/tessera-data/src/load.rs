//! One entry point for every supported volume file format.

use std::path::Path;

use crate::error::{DataError, Result};
use crate::input::regular_file;
use crate::nifti::load_nifti;
use crate::nrrd::load_nrrd;
use crate::raw::{load_raw, RawOptions};
use crate::sniff::{sniff, Sniffed};
use crate::volume::Volume;
use crate::vti::load_vti;

/// Loads `path` as NRRD (`.nrrd`, `.nhdr`), NIfTI (`.nii`, `.nii.gz`), VTK XML image data
/// (`.vti`), extensions in any case; a file with another extension as what its first bytes
/// say ([`crate::sniff`]), else as a raw file. For NRRD, NIfTI and VTI files the header
/// supplies everything but the NaN policy and, where `opts.spacing` is given, the spacing,
/// which then replaces the header's ([`Volume::replaced_spacing`] says what it was). Only
/// regular files are read (no directories, devices or named pipes).
pub fn load_volume(path: &Path, opts: &RawOptions) -> Result<Volume> {
    let volume = load_volume_as_stored(path, opts)?;
    match opts.spacing {
        Some(spacing) => volume.with_spacing(spacing).map_err(|e| e.in_file(path)),
        None => Ok(volume),
    }
}

fn load_volume_as_stored(path: &Path, opts: &RawOptions) -> Result<Volume> {
    // Checked up front so that a mistyped path reports "not found" rather than, say, a
    // complaint about missing --dims for a raw file that does not exist.
    regular_file(path)?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let is_nii_gz = path
        .file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.to_ascii_lowercase().ends_with(".nii.gz"));
    match ext.as_deref() {
        Some("nrrd" | "nhdr") => load_nrrd(path, opts.nan_policy),
        Some("nii") => load_nifti(path, opts.nan_policy),
        Some("vti") => load_vti(path, opts.nan_policy),
        Some("gz") if is_nii_gz => load_nifti(path, opts.nan_policy),
        _ => match sniff(path) {
            Some(Sniffed::VtkXmlImage) => load_vti(path, opts.nan_policy),
            Some(Sniffed::Nrrd) => load_nrrd(path, opts.nan_policy),
            Some(mesh) => Err(DataError::format(
                path,
                format!(
                    "is {}, which holds a tetrahedral mesh, not a volume",
                    mesh.describe()
                ),
            )),
            None => load_raw(path, opts),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::DataError;
    use crate::test_files::test_path;
    use crate::volume::ScalarType;

    #[test]
    fn dispatches_on_extension() {
        let path = test_path("vol.NRRD");
        let mut bytes = b"NRRD0004\ntype: uint16\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n\n".to_vec();
        bytes.extend([0u8; 16]);
        std::fs::write(&path, bytes).expect("write");
        let v = load_volume(&path, &RawOptions::default()).expect("nrrd");
        assert_eq!(v.scalar_type(), ScalarType::U16);

        let path = test_path("vol_2x2x3_uint8.raw");
        std::fs::write(&path, [5u8; 12]).expect("write");
        let v = load_volume(&path, &RawOptions::default()).expect("raw");
        assert_eq!(v.dims(), [2, 2, 3]);
    }

    #[test]
    fn header_spacing_is_kept_unless_replaced() {
        let path = test_path("spaced.nhdr");
        let mut bytes = b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nspacings: 0.5 1 2\nencoding: raw\n\n".to_vec();
        bytes.extend([0u8; 8]);
        let path = path.with_extension("nrrd");
        std::fs::write(&path, bytes).expect("write");
        let v = load_volume(&path, &RawOptions::default()).expect("nrrd");
        assert_eq!((v.spacing(), v.replaced_spacing()), ([0.5, 1.0, 2.0], None));
        let opts = RawOptions {
            spacing: Some([1.0, 1.0, 3.0]),
            ..RawOptions::default()
        };
        let v = load_volume(&path, &opts).expect("nrrd");
        assert_eq!(v.spacing(), [1.0, 1.0, 3.0]);
        assert_eq!(v.replaced_spacing(), Some([0.5, 1.0, 2.0]));

        // A raw file takes the spacing as its own.
        let path = test_path("spaced_2x2x2_uint8.raw");
        std::fs::write(&path, [1u8; 8]).expect("write");
        let v = load_volume(&path, &opts).expect("raw");
        assert_eq!((v.spacing(), v.replaced_spacing()), ([1.0, 1.0, 3.0], None));
    }

    /// A minimal little-endian NIfTI-1 file: 2x2x3 uint8, data at byte 352.
    fn nifti_bytes() -> Vec<u8> {
        let mut bytes = vec![0u8; 352];
        bytes[0..4].copy_from_slice(&348i32.to_le_bytes());
        for (i, d) in [3i16, 2, 2, 3, 1, 1, 1, 1].iter().enumerate() {
            bytes[40 + 2 * i..42 + 2 * i].copy_from_slice(&d.to_le_bytes());
        }
        bytes[70..72].copy_from_slice(&2i16.to_le_bytes());
        bytes[108..112].copy_from_slice(&352f32.to_le_bytes());
        bytes[344..348].copy_from_slice(b"n+1\0");
        bytes.extend([4u8; 12]);
        bytes
    }

    #[test]
    fn dispatches_nifti() {
        use std::io::Write;

        let path = test_path("scan.NII");
        std::fs::write(&path, nifti_bytes()).expect("write");
        let v = load_volume(&path, &RawOptions::default()).expect("nii");
        assert_eq!((v.name(), v.dims()), ("scan", [2, 2, 3]));

        let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        enc.write_all(&nifti_bytes()).expect("compress");
        let path = test_path("scan.Nii.Gz");
        std::fs::write(&path, enc.finish().expect("compress")).expect("write");
        let v = load_volume(&path, &RawOptions::default()).expect("nii.gz");
        assert_eq!((v.name(), v.dims()), ("scan", [2, 2, 3]));

        // Other .gz files are not taken for NIfTI.
        let path = test_path("scan.raw.gz");
        std::fs::write(&path, [0u8; 8]).expect("write");
        let err = load_volume(&path, &RawOptions::default()).expect_err("raw");
        assert!(err.to_string().contains("--dims"), "{err}");
    }

    #[test]
    fn missing_file_and_directory() {
        for name in ["nowhere_2x2x2_uint8.raw", "nowhere.nhdr", "nowhere.nii.gz"] {
            let path = test_path(name);
            let err = load_volume(&path, &RawOptions::default()).expect_err("missing");
            assert!(matches!(err, DataError::Io { .. }), "{err}");
            assert!(err.to_string().contains(name), "{err}");
        }
        let dir = test_path("adir.raw");
        std::fs::create_dir_all(&dir).expect("mkdir");
        let err = load_volume(&dir, &RawOptions::default()).expect_err("dir");
        assert!(err.to_string().contains("adir.raw"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn pipes_and_devices_are_refused() {
        use crate::test_files::{test_fifo, within};
        for name in [
            "pipe.nrrd",
            "pipe.nii",
            "pipe.nii.gz",
            "pipe_2x2x2_uint8.raw",
        ] {
            let pipe = test_fifo(name);
            let err = within(10, move || {
                load_volume(&pipe, &RawOptions::default()).map(|v| v.name().to_string())
            })
            .expect_err("pipe");
            let text = err.to_string();
            assert!(text.contains(name) && text.contains("named pipe"), "{text}");
        }
        let opts = RawOptions {
            dims: Some([2, 2, 2]),
            dtype: Some("uint8".into()),
            ..RawOptions::default()
        };
        let err = within(10, move || {
            load_volume(Path::new("/dev/zero"), &opts).map(|_| ())
        })
        .expect_err("device");
        assert!(err.to_string().contains("character device"), "{err}");
    }
}
