//! One entry point for every supported volume file format.

use std::path::Path;

use crate::error::{DataError, Result};
use crate::nrrd::load_nrrd;
use crate::raw::{load_raw, RawOptions};
use crate::volume::Volume;

/// Loads `path` as NRRD (`.nrrd`, `.nhdr`, any case) or else as a raw file. For NRRD files
/// only `opts.nan_policy` applies; the header supplies everything else.
pub fn load_volume(path: &Path, opts: &RawOptions) -> Result<Volume> {
    // Checked up front so that a mistyped path reports "not found" rather than, say, a
    // complaint about missing --dims for a raw file that does not exist.
    let meta = std::fs::metadata(path).map_err(|e| DataError::io(path, e))?;
    if meta.is_dir() {
        return Err(DataError::format(path, "is a directory, not a volume file"));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("nrrd" | "nhdr") => load_nrrd(path, opts.nan_policy),
        _ => load_raw(path, opts),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raw::test_path;
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
    fn missing_file_and_directory() {
        for name in ["nowhere_2x2x2_uint8.raw", "nowhere.nhdr"] {
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
}
