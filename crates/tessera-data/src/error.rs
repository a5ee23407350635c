//! Errors of the data layer. Every variant that concerns a file names it, so that a message
//! shown to a user on its own (without a backtrace or context chain) says which file is bad
//! and why.

use std::path::{Path, PathBuf};

/// Sample types the loaders accept, as listed in error messages.
pub const SUPPORTED_TYPES: &str =
    "uint8 (u8), uint16 (u16), int8, int16, uint32, int32, float32 (f32, float), float64 (double)";

/// Everything that can go wrong while loading, generating or validating volume data.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// The file could not be opened or read. `error` is deliberately no `#[source]` (nor
    /// named `source`): the message already holds it, and context chains printed with `{:#}`
    /// (anyhow) would say "No such file or directory" twice.
    #[error("{}: {error}", .path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },

    /// A header or file name could not be understood.
    #[error("{}: {message}", .path.display())]
    Format { path: PathBuf, message: String },

    /// The amount of sample data does not match what the header or options describe.
    #[error("{}: {}", .path.display(), size_problem(*.expected_bytes, *.found_bytes, .detail))]
    SizeMismatch {
        path: PathBuf,
        expected_bytes: u64,
        found_bytes: u64,
        detail: String,
    },

    /// The sample type is not one the loaders can convert.
    #[error(
        "{}: unsupported sample type '{name}' (supported: {SUPPORTED_TYPES})",
        .path.display()
    )]
    UnknownType { path: PathBuf, name: String },

    /// Dimensions that leave no cells to interpolate in.
    #[error(
        "{what}: invalid dimensions {}x{}x{}: a volume needs at least 2 samples along every axis",
        .dims[0], .dims[1], .dims[2]
    )]
    InvalidDims { what: String, dims: [u64; 3] },

    /// NaN or infinite samples, which would poison value ranges, gradients and isosurfaces.
    #[error(
        "{path_or_name}: {count} non-finite (NaN/Inf) sample(s), first at voxel ({}, {}, {}); \
         pass --nan-fill VALUE to load it with VALUE in their place",
        .first[0], .first[1], .first[2]
    )]
    NonFinite {
        path_or_name: String,
        count: u64,
        first: [u32; 3],
    },

    /// Any other bad argument.
    #[error("{0}")]
    Invalid(String),

    /// An error about what a data spec names, with the spec (or another label) in front.
    /// `inner` is deliberately no `#[source]`: the message already holds it, and context
    /// chains printed with `{:#}` (anyhow) would show it twice.
    #[error("{label}: {inner}")]
    Labelled {
        label: String,
        inner: Box<DataError>,
    },
}

/// Result type of the data layer.
pub type Result<T> = std::result::Result<T, DataError>;

fn size_problem(expected: u64, found: u64, detail: &str) -> String {
    let what = if found < expected {
        "data is truncated".to_string()
    } else {
        format!("has {} extra bytes", found - expected)
    };
    format!("{what}: expected {expected} bytes, found {found} ({detail})")
}

impl DataError {
    pub(crate) fn io(path: &Path, error: std::io::Error) -> Self {
        DataError::Io {
            path: path.to_path_buf(),
            error,
        }
    }

    pub(crate) fn format(path: &Path, message: impl Into<String>) -> Self {
        DataError::Format {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// This error with `label` in front of its message.
    pub fn labelled(self, label: impl Into<String>) -> Self {
        DataError::Labelled {
            label: label.into(),
            inner: Box::new(self),
        }
    }

    /// Volume validation only knows the volume's name (a file stem); a loader re-labels the
    /// errors with the full path so that the message names the file the user passed.
    pub(crate) fn in_file(self, path: &Path) -> Self {
        let label = path.display().to_string();
        match self {
            DataError::InvalidDims { dims, .. } => DataError::InvalidDims { what: label, dims },
            DataError::NonFinite { count, first, .. } => DataError::NonFinite {
                path_or_name: label,
                count,
                first,
            },
            DataError::Invalid(message) => DataError::Format {
                path: path.to_path_buf(),
                message,
            },
            other => other,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_mismatch_wording() {
        let short = DataError::SizeMismatch {
            path: PathBuf::from("/d/a.raw"),
            expected_bytes: 100,
            found_bytes: 60,
            detail: "x".into(),
        };
        let text = short.to_string();
        assert!(
            text.contains("a.raw") && text.contains("truncated"),
            "{text}"
        );
        assert!(text.contains("100") && text.contains("60"), "{text}");

        let long = DataError::SizeMismatch {
            path: PathBuf::from("/d/b.raw"),
            expected_bytes: 100,
            found_bytes: 108,
            detail: "x".into(),
        };
        let text = long.to_string();
        assert!(
            text.contains("b.raw") && text.contains("has 8 extra bytes"),
            "{text}"
        );
    }

    #[test]
    fn in_file_relabels_volume_errors() {
        let err = DataError::NonFinite {
            path_or_name: "stem".into(),
            count: 2,
            first: [1, 2, 3],
        }
        .in_file(Path::new("/x/stem.raw"));
        let text = err.to_string();
        assert!(
            text.contains("stem.raw") && text.contains("(1, 2, 3)"),
            "{text}"
        );

        let err = DataError::InvalidDims {
            what: "v".into(),
            dims: [0, 4, 4],
        }
        .in_file(Path::new("v.raw"));
        assert!(err.to_string().contains("v.raw"));
        assert!(err.to_string().contains("0x4x4"));
    }

    #[test]
    fn labelled_shows_the_inner_message_once() {
        let err = DataError::Invalid("bad N".into()).labelled("tets:box:0");
        assert_eq!(err.to_string(), "tets:box:0: bad N");
        assert!(std::error::Error::source(&err).is_none());
    }

    #[test]
    fn io_error_shows_the_reason_once() {
        let missing = std::io::Error::from(std::io::ErrorKind::NotFound);
        let err = DataError::io(Path::new("/d/gone.nrrd"), missing);
        assert!(err.to_string().starts_with("/d/gone.nrrd: "), "{err}");
        // A chain printer (anyhow's `{:#}`) appends every source: there must be none.
        assert!(std::error::Error::source(&err).is_none());
    }

    #[test]
    fn non_finite_advice_names_the_flag() {
        let err = DataError::NonFinite {
            path_or_name: "v.nii".into(),
            count: 1,
            first: [0, 0, 0],
        };
        let text = err.to_string();
        assert!(
            text.contains("--nan-fill") && !text.contains("NanPolicy"),
            "{text}"
        );
    }

    #[test]
    fn unknown_type_lists_supported() {
        let err = DataError::UnknownType {
            path: PathBuf::from("q.raw"),
            name: "complex".into(),
        };
        let text = err.to_string();
        assert!(text.contains("q.raw") && text.contains("complex"));
        assert!(text.contains("uint16") && text.contains("float32"));
    }
}
