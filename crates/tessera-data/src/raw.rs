//! Headerless ("raw") volume files, such as those of the Open SciVis Datasets collection.
//!
//! Sample type conversion (shared with the NRRD loader): `uint8` and `uint16` data stay in
//! their native type, so they can be uploaded as UNORM textures without growing; `int8`,
//! `int16`, `uint32`, `int32`, `float32` and `float64` are converted to `f32` samples
//! (32-bit integers and doubles may lose precision in the process).

use std::io::{Seek, SeekFrom};
use std::path::Path;

use crate::error::{DataError, Result};
use crate::input::{open_regular, sample_bytes};
use crate::sample_data::{read_samples, sample_count, Supply};
use crate::volume::{NanPolicy, Volume};

/// Byte order of multi-byte samples in a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Endian {
    #[default]
    Little,
    Big,
}

/// The sample type as stored in a file, before conversion to a [`crate::ScalarType`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    F32,
    F64,
}

impl SourceType {
    pub fn size_bytes(self) -> usize {
        match self {
            SourceType::U8 | SourceType::I8 => 1,
            SourceType::U16 | SourceType::I16 => 2,
            SourceType::U32 | SourceType::I32 | SourceType::F32 => 4,
            SourceType::F64 => 8,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SourceType::U8 => "uint8",
            SourceType::I8 => "int8",
            SourceType::U16 => "uint16",
            SourceType::I16 => "int16",
            SourceType::U32 => "uint32",
            SourceType::I32 => "int32",
            SourceType::F32 => "float32",
            SourceType::F64 => "float64",
        }
    }
}

/// How to interpret a raw file. Unset `dims`/`dtype` are taken from the file name.
#[derive(Clone, Debug)]
pub struct RawOptions {
    pub dims: Option<[u32; 3]>,
    pub dtype: Option<String>,
    pub endian: Endian,
    /// Bytes to skip at the start of the file.
    pub header_bytes: u64,
    /// Spacing between samples: that of a raw file (`None`: 1 on every axis), and for any
    /// other volume (a header format, a procedural one) a replacement for what it says
    /// (see [`crate::Volume::replaced_spacing`]).
    pub spacing: Option<[f32; 3]>,
    pub nan_policy: NanPolicy,
}

impl Default for RawOptions {
    fn default() -> Self {
        RawOptions {
            dims: None,
            dtype: None,
            endian: Endian::Little,
            header_bytes: 0,
            spacing: None,
            nan_policy: NanPolicy::Reject,
        }
    }
}

/// Reads dimensions and type from an Open SciVis style name such as
/// `bonsai_256x256x256_uint8.raw`: the type is the last `_`-separated word of the stem and
/// the dimensions the last `NxNxN` word before it.
pub fn parse_scivis_name(file_name: &str) -> Option<([u32; 3], String)> {
    let base = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
    let stem = base.rsplit_once('.').map_or(base, |(s, _)| s);
    let words: Vec<&str> = stem.split('_').collect();
    let (dtype, before) = words.split_last()?;
    let dims = before.iter().rev().find_map(|w| parse_dims_word(w))?;
    if dtype.is_empty() {
        return None;
    }
    Some((dims, dtype.to_string()))
}

fn parse_dims_word(word: &str) -> Option<[u32; 3]> {
    let mut parts = word.split(['x', 'X']);
    let mut dims = [0u32; 3];
    for d in &mut dims {
        let part = parts.next()?;
        if part.is_empty() || !part.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        *d = part.parse().ok()?;
    }
    parts.next().is_none().then_some(dims)
}

/// Maps a user-facing type name to a [`SourceType`]; `path` is only used for the error.
pub fn scalar_from_name(path: &Path, name: &str) -> Result<SourceType> {
    let t = match name.trim().to_ascii_lowercase().as_str() {
        "uint8" | "u8" => SourceType::U8,
        "int8" | "i8" => SourceType::I8,
        "uint16" | "u16" => SourceType::U16,
        "int16" | "i16" => SourceType::I16,
        "uint32" | "u32" => SourceType::U32,
        "int32" | "i32" => SourceType::I32,
        "float32" | "f32" | "float" => SourceType::F32,
        "float64" | "f64" | "double" => SourceType::F64,
        _ => {
            return Err(DataError::UnknownType {
                path: path.to_path_buf(),
                name: name.to_string(),
            })
        }
    };
    Ok(t)
}

/// Loads a headerless volume. See the module documentation for type conversions.
pub fn load_raw(path: &Path, opts: &RawOptions) -> Result<Volume> {
    let mut file = open_regular(path)?;
    let file_name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let from_name = file_name.as_deref().and_then(parse_scivis_name);
    let dims = opts.dims.or(from_name.as_ref().map(|(d, _)| *d));
    let dtype = opts.dtype.clone().or(from_name.map(|(_, t)| t));
    let (Some(dims), Some(dtype)) = (dims, dtype) else {
        return Err(DataError::format(
            path,
            "read as a raw volume (neither its extension nor its first bytes name a known \
             format), but its dimensions and sample type are unknown: pass --dims WxHxD and \
             --dtype TYPE, or name the file like name_256x256x256_uint8.raw",
        ));
    };
    let source = scalar_from_name(path, &dtype)?;
    if dims.iter().any(|&d| d < 2) {
        return Err(DataError::InvalidDims {
            what: path.display().to_string(),
            dims: dims.map(u64::from),
        });
    }
    let count = sample_count(path, dims)?;
    let data_bytes = sample_bytes(path, count as u64, source)?;
    let expected = opts.header_bytes.saturating_add(data_bytes);
    let found = file.metadata().map_err(|e| DataError::io(path, e))?.len();
    if found != expected {
        return Err(DataError::SizeMismatch {
            path: path.to_path_buf(),
            expected_bytes: expected,
            found_bytes: found,
            detail: format!(
                "{}x{}x{} {} samples after a {}-byte header",
                dims[0],
                dims[1],
                dims[2],
                source.name(),
                opts.header_bytes
            ),
        });
    }
    file.seek(SeekFrom::Start(opts.header_bytes))
        .map_err(|e| DataError::io(path, e))?;
    let samples = read_samples(&mut file, count, source, opts.endian, Supply::Checked, path)?;
    let name = path
        .file_stem()
        .map_or_else(|| "volume".into(), |s| s.to_string_lossy().into_owned());
    let spacing = opts.spacing.unwrap_or([1.0; 3]);
    Volume::with_nan_policy(name, dims, spacing, samples, opts.nan_policy)
        .map_err(|e| e.in_file(path))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_files::test_path;
    use crate::volume::{Samples, ScalarType};

    fn write(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let path = test_path(name);
        std::fs::write(&path, bytes).expect("write test file");
        path
    }

    fn opts(dims: [u32; 3], dtype: &str) -> RawOptions {
        RawOptions {
            dims: Some(dims),
            dtype: Some(dtype.into()),
            ..RawOptions::default()
        }
    }

    #[test]
    fn scivis_names() {
        let parsed = parse_scivis_name("bonsai_256x256x256_uint8.raw");
        assert_eq!(parsed, Some(([256, 256, 256], "uint8".to_string())));
        let parsed = parse_scivis_name("richtmyer_meshkov_2048x2048x1920_uint8.raw");
        assert_eq!(parsed, Some(([2048, 2048, 1920], "uint8".to_string())));
        let parsed = parse_scivis_name("/data/a_1x2x3_b_4x5x6_float32.raw");
        assert_eq!(parsed, Some(([4, 5, 6], "float32".to_string())));
        assert_eq!(parse_scivis_name("bonsai.raw"), None);
        assert_eq!(parse_scivis_name("bonsai_256x256_uint8.raw"), None);
        assert_eq!(parse_scivis_name("256x256x256.raw"), None);
    }

    #[test]
    fn uint8_from_file_name() {
        let data: Vec<u8> = (0..24).collect();
        let path = write("tiny_2x3x4_uint8.raw", &data);
        let v = load_raw(&path, &RawOptions::default()).expect("load");
        assert_eq!(v.dims(), [2, 3, 4]);
        assert_eq!(v.name(), "tiny_2x3x4_uint8");
        assert_eq!(v.scalar_type(), ScalarType::U8);
        assert_eq!(v.bytes(), &data[..]);
        assert_eq!(v.value_range(), (0.0, 23.0));
    }

    #[test]
    fn uint16_both_endians_and_header() {
        let values: Vec<u16> = (0..8).map(|i| 0x0102 * (i + 1)).collect();
        for endian in [Endian::Little, Endian::Big] {
            let mut bytes = vec![0xEE; 5];
            for v in &values {
                bytes.extend(match endian {
                    Endian::Little => v.to_le_bytes(),
                    Endian::Big => v.to_be_bytes(),
                });
            }
            let path = write("w.raw", &bytes);
            let o = RawOptions {
                endian,
                header_bytes: 5,
                ..opts([2, 2, 2], "u16")
            };
            let v = load_raw(&path, &o).expect("load");
            assert_eq!(v.samples(), &Samples::U16(values.clone()), "{endian:?}");
        }
    }

    #[test]
    fn converted_types() {
        let i16s: [i16; 8] = [-300, -1, 0, 1, 2, 3, 4, 300];
        let be: Vec<u8> = i16s.iter().flat_map(|v| v.to_be_bytes()).collect();
        let v = load_raw(
            &write("s.raw", &be),
            &RawOptions {
                endian: Endian::Big,
                ..opts([2, 2, 2], "int16")
            },
        )
        .expect("load");
        let want: Vec<f32> = i16s.iter().map(|&x| x as f32).collect();
        assert_eq!(v.samples(), &Samples::F32(want));

        let cases: [(&str, Vec<u8>, Vec<f32>); 4] = [
            (
                "int8",
                vec![0x80, 0xFF, 0, 1, 2, 3, 4, 127],
                vec![-128., -1., 0., 1., 2., 3., 4., 127.],
            ),
            (
                "uint32",
                (0..8u32).flat_map(|i| (i * 1000).to_le_bytes()).collect(),
                (0..8).map(|i| i as f32 * 1000.0).collect(),
            ),
            (
                "int32",
                (0..8i32).flat_map(|i| (-i).to_le_bytes()).collect(),
                (0..8).map(|i| -i as f32).collect(),
            ),
            (
                "double",
                (0..8)
                    .flat_map(|i| (i as f64 * 0.5).to_le_bytes())
                    .collect(),
                (0..8).map(|i| i as f32 * 0.5).collect(),
            ),
        ];
        for (dtype, bytes, want) in cases {
            let v = load_raw(&write("c.raw", &bytes), &opts([2, 2, 2], dtype)).expect(dtype);
            assert_eq!(v.samples(), &Samples::F32(want), "{dtype}");
        }
        let be: Vec<u8> = (0..8)
            .flat_map(|i| (i as f32 - 0.25).to_be_bytes())
            .collect();
        let o = RawOptions {
            endian: Endian::Big,
            ..opts([2, 2, 2], "float32")
        };
        let v = load_raw(&write("f.raw", &be), &o).expect("load");
        assert_eq!(v.texel(1, 1, 1), 6.75);
    }

    #[test]
    fn truncated_and_oversized() {
        let path = write("cut_4x4x4_uint16.raw", &[0u8; 100]);
        let err = load_raw(&path, &RawOptions::default()).unwrap_err();
        let text = err.to_string();
        assert!(matches!(
            err,
            DataError::SizeMismatch {
                expected_bytes: 128,
                found_bytes: 100,
                ..
            }
        ));
        assert!(
            text.contains("cut_4x4x4_uint16.raw") && text.contains("truncated"),
            "{text}"
        );

        let path = write("big_2x2x2_uint8.raw", &[0u8; 10]);
        let err = load_raw(&path, &RawOptions::default()).unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, DataError::SizeMismatch { .. }));
        assert!(
            text.contains("big_2x2x2_uint8.raw") && text.contains("2 extra bytes"),
            "{text}"
        );
    }

    #[test]
    fn explicit_dims_disagreeing_with_file() {
        let path = write("named_4x4x4_uint8.raw", &[7u8; 64]);
        let err = load_raw(&path, &opts([4, 4, 2], "uint8")).unwrap_err();
        assert!(matches!(err, DataError::SizeMismatch { .. }));
        assert!(err.to_string().contains("named_4x4x4_uint8.raw"));
        let err = load_raw(
            &path,
            &RawOptions {
                dtype: Some("uint16".into()),
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(err.to_string().contains("truncated"), "{err}");
    }

    #[test]
    fn missing_metadata_unknown_type_bad_dims() {
        let path = write("anonymous.raw", &[0u8; 8]);
        let err = load_raw(&path, &RawOptions::default()).unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, DataError::Format { .. }));
        assert!(
            text.contains("anonymous.raw") && text.contains("--dims"),
            "{text}"
        );

        let path = write("odd_2x2x2_complex64.raw", &[0u8; 8]);
        let err = load_raw(&path, &RawOptions::default()).unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, DataError::UnknownType { .. }));
        assert!(
            text.contains("odd_2x2x2_complex64.raw") && text.contains("float32"),
            "{text}"
        );

        let path = write("flat_0x4x4_uint8.raw", &[]);
        let err = load_raw(&path, &RawOptions::default()).unwrap_err();
        assert!(matches!(err, DataError::InvalidDims { .. }));
        assert!(err.to_string().contains("flat_0x4x4_uint8.raw"));

        let err = load_raw(&test_path("absent.raw"), &RawOptions::default()).unwrap_err();
        assert!(matches!(err, DataError::Io { .. }));
        assert!(err.to_string().contains("absent.raw"));
    }

    #[test]
    fn nan_samples() {
        let mut values = [1.0f32; 8];
        values[6] = f32::NAN; // voxel (0, 1, 1)
        values[7] = f32::NEG_INFINITY;
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let path = write("holes_2x2x2_float32.raw", &bytes);
        let err = load_raw(&path, &RawOptions::default()).unwrap_err();
        let text = err.to_string();
        assert!(matches!(
            err,
            DataError::NonFinite {
                count: 2,
                first: [0, 1, 1],
                ..
            }
        ));
        assert!(
            text.contains("holes_2x2x2_float32.raw") && text.contains("(0, 1, 1)"),
            "{text}"
        );

        let o = RawOptions {
            nan_policy: NanPolicy::Replace(0.0),
            ..RawOptions::default()
        };
        let v = load_raw(&path, &o).expect("replaced");
        assert_eq!(v.texel(0, 1, 1), 0.0);
        assert_eq!(v.texel(1, 1, 1), 0.0);
        assert_eq!(v.value_range(), (0.0, 1.0));
    }
}
