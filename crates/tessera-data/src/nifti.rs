//! NIfTI volumes stored in one file: NIfTI-1 (`.nii`, 348-byte header, magic `n+1`) and
//! NIfTI-2 (540-byte header, magic `n+2`, 64-bit sizes), either plain or gzip-compressed
//! (`.nii.gz`). Compression is recognised by the gzip magic bytes (1f 8b), not by the name,
//! and the byte order by which reading of `sizeof_hdr` gives 348 (or 540).
//!
//! Sample types are converted as for raw files (see [`crate::raw`]): `uint8` and `uint16`
//! stay native, `int8`, `int16`, `int32`, `uint32`, `float32` and `float64` become `f32`.
//! Complex, RGB, 64-bit integer, 128-bit float and 1-bit data are refused with
//! [`DataError::UnknownType`].
//!
//! Intensity scaling: when `scl_slope` is finite and non-zero and the pair
//! (`scl_slope`, `scl_inter`) is not the identity (1, 0), every sample is replaced by
//! `value * scl_slope + scl_inter` (computed in `f64`) and the volume holds `f32` samples,
//! whatever the stored type — a scaled `uint8` file therefore loads as `f32`. A slope of 0
//! means "no scaling", as the standard says, and a non-finite `scl_inter` counts as 0.
//! [`NanPolicy::Replace`] applies after scaling, so its value is in scaled units.
//!
//! Only dimensions 1..3 may exceed 1: `dim[0]` must be 3, or 4..7 with every further
//! dimension equal to 1 (time series and vector data are refused).
//!
//! Read from the header: `dim`, `datatype`, `pixdim[1..=3]` (the spacing), `vox_offset` and
//! `scl_slope`/`scl_inter`. Ignored: the qform/sform orientation (samples stay in file order,
//! i fastest, then j, then k), units, intent codes, `cal_min`/`cal_max`; extensions are
//! skipped by starting at `vox_offset`.
//!
//! Deliberate leniencies: a spacing that is zero, negative or not finite means 1 (many files
//! leave `pixdim` at 0); a `vox_offset` of 0 means the data follows the header and its 4-byte
//! extension flag; bytes after the data are ignored.

use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use flate2::bufread::MultiGzDecoder;
use rayon::prelude::*;

use crate::error::{DataError, Result};
use crate::raw::{fill, read_samples, sample_count, Endian, SourceType};
use crate::volume::{NanPolicy, Samples, Volume};

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];
const NIFTI1_HEADER: usize = 348;
const NIFTI2_HEADER: usize = 540;
/// The 4-byte extension flag that follows the header in a single file.
const EXTENSION_FLAG: u64 = 4;

/// What the header says, after validation.
struct Header {
    header_len: u64,
    endian: Endian,
    source: SourceType,
    dims: [u32; 3],
    spacing: [f32; 3],
    vox_offset: u64,
    /// `(slope, intercept)`, present only when it changes the values.
    scaling: Option<(f64, f64)>,
}

/// The header fields this loader uses, as stored (widened to the NIfTI-2 types).
struct RawHeader {
    version: u8,
    dim: [i64; 8],
    datatype: i16,
    pixdim: [f64; 8],
    /// NIfTI-1 stores it as a float, NIfTI-2 as an integer.
    vox_offset: f64,
    scl_slope: f64,
    scl_inter: f64,
}

/// Loads a single-file NIfTI-1 or NIfTI-2 volume, gzip-compressed or not. See the module
/// documentation for type conversion, intensity scaling and what is ignored.
pub fn load_nifti(path: &Path, nan_policy: NanPolicy) -> Result<Volume> {
    let io_err = |e| DataError::io(path, e);
    let mut file = File::open(path).map_err(io_err)?;
    let mut magic = [0u8; 2];
    let got = fill(&mut file, &mut magic).map_err(io_err)?;
    file.seek(SeekFrom::Start(0)).map_err(io_err)?;

    let (header, samples) = if got == magic.len() && magic == GZIP_MAGIC {
        let mut decoder = MultiGzDecoder::new(BufReader::new(file));
        read_nifti(&mut decoder, path, None).map_err(|e| match e {
            DataError::Io { path, source } => gzip_error(&path, source),
            other => other,
        })?
    } else {
        let len = file.metadata().map_err(io_err)?.len();
        read_nifti(&mut BufReader::new(file), path, Some(len))?
    };
    let samples = match header.scaling {
        Some((slope, inter)) => rescale(samples, slope, inter),
        None => samples,
    };
    Volume::with_nan_policy(
        volume_name(path),
        header.dims,
        header.spacing,
        samples,
        nan_policy,
    )
    .map_err(|e| e.in_file(path))
}

/// Reads header and samples from the (decompressed) stream. `file_len` is the size of an
/// uncompressed file, which lets a short file be reported before anything is allocated.
fn read_nifti(
    reader: &mut impl Read,
    path: &Path,
    file_len: Option<u64>,
) -> Result<(Header, Samples)> {
    let header = read_header(reader, path)?;
    let count = sample_count(path, header.dims)?;
    let need = count as u64 * header.source.size_bytes() as u64;
    let [nx, ny, nz] = header.dims;
    let what = if file_len.is_some() {
        ""
    } else {
        "decompressed "
    };
    let truncated = |found: u64| DataError::SizeMismatch {
        path: path.to_path_buf(),
        expected_bytes: need,
        found_bytes: found,
        detail: format!(
            "{nx}x{ny}x{nz} {} samples starting at {what}byte {} (vox_offset)",
            header.source.name(),
            header.vox_offset
        ),
    };
    if let Some(len) = file_len {
        let found = len.saturating_sub(header.vox_offset);
        if found < need {
            return Err(truncated(found));
        }
    }
    let gap = header.vox_offset - header.header_len;
    if skip(reader, gap).map_err(|e| DataError::io(path, e))? < gap {
        return Err(truncated(0));
    }
    let samples =
        read_samples(reader, count, header.source, header.endian, path).map_err(|e| match e {
            DataError::SizeMismatch { found_bytes, .. } => truncated(found_bytes),
            other => other,
        })?;
    Ok((header, samples))
}

/// Reads the NIfTI-1 or NIfTI-2 header, leaving `reader` just after it.
fn read_header(reader: &mut impl Read, path: &Path) -> Result<Header> {
    let mut buf = [0u8; NIFTI2_HEADER];
    let got = fill(reader, &mut buf[..4]).map_err(|e| DataError::io(path, e))?;
    if got < 4 {
        let msg = format!("not a NIfTI file: only {got} bytes long");
        return Err(DataError::format(path, msg));
    }
    let first = [buf[0], buf[1], buf[2], buf[3]];
    let (len, endian) = match (i32::from_le_bytes(first), i32::from_be_bytes(first)) {
        (348, _) => (NIFTI1_HEADER, Endian::Little),
        (_, 348) => (NIFTI1_HEADER, Endian::Big),
        (540, _) => (NIFTI2_HEADER, Endian::Little),
        (_, 540) => (NIFTI2_HEADER, Endian::Big),
        (n, _) => {
            let msg = format!(
                "not a NIfTI file: sizeof_hdr (first 4 bytes) is {n}, expected 348 \
                 (NIfTI-1) or 540 (NIfTI-2)"
            );
            return Err(DataError::format(path, msg));
        }
    };
    let got = fill(reader, &mut buf[4..len]).map_err(|e| DataError::io(path, e))?;
    if got < len - 4 {
        let msg = format!(
            "header is truncated: the file ends after {} of the {len} header bytes",
            got + 4
        );
        return Err(DataError::format(path, msg));
    }
    let fields = Fields {
        bytes: &buf[..len],
        big: endian == Endian::Big,
    };
    let raw = if len == NIFTI1_HEADER {
        parse_nifti1(&fields, path)?
    } else {
        parse_nifti2(&fields, path)?
    };
    validate(raw, len as u64, endian, path)
}

fn parse_nifti1(f: &Fields, path: &Path) -> Result<RawHeader> {
    check_magic(f.bytes, 344, 1, path)?;
    Ok(RawHeader {
        version: 1,
        dim: std::array::from_fn(|i| i64::from(f.i16(40 + 2 * i))),
        datatype: f.i16(70),
        pixdim: std::array::from_fn(|i| f64::from(f.f32(76 + 4 * i))),
        vox_offset: f64::from(f.f32(108)),
        scl_slope: f64::from(f.f32(112)),
        scl_inter: f64::from(f.f32(116)),
    })
}

fn parse_nifti2(f: &Fields, path: &Path) -> Result<RawHeader> {
    check_magic(f.bytes, 4, 2, path)?;
    Ok(RawHeader {
        version: 2,
        dim: std::array::from_fn(|i| f.i64(16 + 8 * i)),
        datatype: f.i16(12),
        pixdim: std::array::from_fn(|i| f.f64(104 + 8 * i)),
        vox_offset: f.i64(168) as f64,
        scl_slope: f.f64(176),
        scl_inter: f.f64(184),
    })
}

/// Single files carry `n+1\0` / `n+2\0`; `ni1\0` / `ni2\0` mark a `.hdr` of a header/image
/// pair, and anything else (e.g. an Analyze 7.5 header) is not NIfTI.
fn check_magic(bytes: &[u8], at: usize, version: u8, path: &Path) -> Result<()> {
    let magic = &bytes[at..at + 4];
    let digit = b'0' + version;
    if magic == [b'n', b'+', digit, 0] {
        return Ok(());
    }
    let msg = if magic == [b'n', b'i', digit, 0] {
        format!(
            "is the header of a NIfTI-{version} .hdr/.img pair (magic \"ni{version}\"); \
             only single-file .nii/.nii.gz volumes are supported"
        )
    } else {
        format!(
            "not a NIfTI-{version} file: expected magic \"n+{version}\\0\" at byte {at}, \
             found {:?} (an Analyze 7.5 header?)",
            String::from_utf8_lossy(magic)
        )
    };
    Err(DataError::format(path, msg))
}

fn validate(raw: RawHeader, header_len: u64, endian: Endian, path: &Path) -> Result<Header> {
    let fail = |msg: String| DataError::format(path, msg);
    let dim = raw.dim;
    let ndim = dim[0];
    if !(3..=7).contains(&ndim) {
        return Err(fail(format!(
            "dim[0]={ndim}: only 3-D scalar volumes are supported (dim[0]=3, or 4..7 with \
             dim[4..] all 1)"
        )));
    }
    for (i, &d) in dim.iter().enumerate().take(ndim as usize + 1).skip(4) {
        if d != 1 {
            let what = match i {
                4 => format!("has {d} volumes (dim[4]={d})"),
                5 => format!("has {d} components per voxel (dim[5]={d})"),
                _ => format!("has dim[{i}]={d}"),
            };
            return Err(fail(format!(
                "{what}; only 3-D scalar volumes are supported"
            )));
        }
    }
    if dim[1..4].iter().any(|&d| d < 2) {
        return Err(DataError::InvalidDims {
            what: path.display().to_string(),
            dims: [dim[1], dim[2], dim[3]].map(|d| d.max(0) as u64),
        });
    }
    let mut dims = [0u32; 3];
    for (axis, out) in dims.iter_mut().enumerate() {
        let d = dim[axis + 1];
        *out = u32::try_from(d).map_err(|_| fail(format!("dim[{}]={d} is too large", axis + 1)))?;
    }

    let source = nifti_type(raw.datatype).map_err(|name| DataError::UnknownType {
        path: path.to_path_buf(),
        name,
    })?;

    let spacing = [1, 2, 3].map(|i| {
        let s = raw.pixdim[i] as f32;
        if s.is_finite() && s > 0.0 {
            s
        } else {
            1.0
        }
    });

    let offset = raw.vox_offset;
    let vox_offset = if offset == 0.0 {
        header_len + EXTENSION_FLAG
    } else if offset.is_finite() && offset.fract() == 0.0 && offset >= header_len as f64 {
        // Float to integer casts saturate, and a huge offset just reads as truncated data.
        offset as u64
    } else {
        return Err(fail(format!(
            "bad vox_offset {offset}: the data of a single-file NIfTI-{} must start at a \
             whole byte at or after the {header_len}-byte header",
            raw.version
        )));
    };

    let (slope, inter) = (raw.scl_slope, raw.scl_inter);
    let inter = if inter.is_finite() { inter } else { 0.0 };
    let scaling = (slope.is_finite() && slope != 0.0 && (slope, inter) != (1.0, 0.0))
        .then_some((slope, inter));

    Ok(Header {
        header_len,
        endian,
        source,
        dims,
        spacing,
        vox_offset,
        scaling,
    })
}

/// Maps a NIfTI datatype code to a [`SourceType`], or to a description for the error.
fn nifti_type(code: i16) -> std::result::Result<SourceType, String> {
    Ok(match code {
        2 => SourceType::U8,
        4 => SourceType::I16,
        8 => SourceType::I32,
        16 => SourceType::F32,
        64 => SourceType::F64,
        256 => SourceType::I8,
        512 => SourceType::U16,
        768 => SourceType::U32,
        _ => {
            let name = match code {
                0 => "unknown",
                1 => "binary (1 bit)",
                32 => "complex64",
                128 => "rgb24",
                1024 => "int64",
                1280 => "uint64",
                1536 => "float128",
                1792 => "complex128",
                2048 => "complex256",
                2304 => "rgba32",
                _ => "not a NIfTI type",
            };
            return Err(format!("{name} (NIfTI datatype {code})"));
        }
    })
}

/// Little- or big-endian reads at fixed header offsets.
struct Fields<'a> {
    bytes: &'a [u8],
    big: bool,
}

impl Fields<'_> {
    fn take<const N: usize>(&self, at: usize) -> [u8; N] {
        let mut out = [0u8; N];
        out.copy_from_slice(&self.bytes[at..at + N]);
        if self.big {
            out.reverse();
        }
        // `out` is now little-endian.
        out
    }

    fn i16(&self, at: usize) -> i16 {
        i16::from_le_bytes(self.take(at))
    }

    fn i64(&self, at: usize) -> i64 {
        i64::from_le_bytes(self.take(at))
    }

    fn f32(&self, at: usize) -> f32 {
        f32::from_le_bytes(self.take(at))
    }

    fn f64(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.take(at))
    }
}

/// `value * slope + inter` for every sample, as `f32`.
fn rescale(samples: Samples, slope: f64, inter: f64) -> Samples {
    let map = |x: f32| (f64::from(x) * slope + inter) as f32;
    let values = match samples {
        Samples::U8(v) => v.par_iter().map(|&x| map(f32::from(x))).collect(),
        Samples::U16(v) => v.par_iter().map(|&x| map(f32::from(x))).collect(),
        Samples::F32(mut v) => {
            v.par_iter_mut().for_each(|x| *x = map(*x));
            v
        }
    };
    Samples::F32(values)
}

/// Discards up to `n` bytes; returns how many there were.
fn skip(reader: &mut impl Read, n: u64) -> io::Result<u64> {
    let mut buf = [0u8; 8192];
    let mut done = 0;
    while done < n {
        let want = (n - done).min(buf.len() as u64) as usize;
        let got = fill(reader, &mut buf[..want])?;
        done += got as u64;
        if got < want {
            break;
        }
    }
    Ok(done)
}

fn gzip_error(path: &Path, e: io::Error) -> DataError {
    match e.kind() {
        io::ErrorKind::InvalidData | io::ErrorKind::InvalidInput => {
            DataError::format(path, format!("corrupt gzip data: {e}"))
        }
        _ => DataError::io(path, e),
    }
}

/// The file name without `.nii.gz` or `.nii` (any case), or else without its extension.
fn volume_name(path: &Path) -> String {
    let Some(file_name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return "volume".into();
    };
    let lower = file_name.to_ascii_lowercase();
    let stem = [".nii.gz", ".nii"]
        .iter()
        .find(|suffix| lower.ends_with(*suffix))
        .map(|suffix| file_name[..file_name.len() - suffix.len()].to_string())
        .or_else(|| path.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_default();
    if stem.is_empty() {
        "volume".into()
    } else {
        stem
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;
    use std::path::PathBuf;

    use flate2::write::GzEncoder;

    use super::*;
    use crate::raw::test_path;
    use crate::volume::ScalarType;

    /// A header to write: NIfTI-1 or -2, either byte order. `vox_offset` 0 means "right after
    /// the header and extension flag"; the writer pads up to it.
    #[derive(Clone)]
    struct Nii {
        version: u8,
        big: bool,
        dim: [i64; 8],
        datatype: i16,
        pixdim: [f64; 8],
        vox_offset: f64,
        slope: f64,
        inter: f64,
        magic: Option<[u8; 4]>,
    }

    impl Nii {
        fn new(dims: [i64; 3], datatype: i16) -> Nii {
            Nii {
                version: 1,
                big: false,
                dim: [3, dims[0], dims[1], dims[2], 1, 1, 1, 1],
                datatype,
                pixdim: [1.0; 8],
                vox_offset: 0.0,
                slope: 0.0,
                inter: 0.0,
                magic: None,
            }
        }

        fn bytes(&self, data: &[u8]) -> Vec<u8> {
            let (len, magic_at) = match self.version {
                1 => (NIFTI1_HEADER, 344),
                _ => (NIFTI2_HEADER, 4),
            };
            let mut h = vec![0u8; len];
            let big = self.big;
            let mut put = |at: usize, le: &[u8]| {
                let mut b = le.to_vec();
                if big {
                    b.reverse();
                }
                h[at..at + b.len()].copy_from_slice(&b);
            };
            put(0, &(len as i32).to_le_bytes());
            let offset = if self.vox_offset == 0.0 {
                len as f64 + 4.0
            } else {
                self.vox_offset
            };
            if self.version == 1 {
                for (i, d) in self.dim.iter().enumerate() {
                    put(40 + 2 * i, &(*d as i16).to_le_bytes());
                }
                put(70, &self.datatype.to_le_bytes());
                for (i, p) in self.pixdim.iter().enumerate() {
                    put(76 + 4 * i, &(*p as f32).to_le_bytes());
                }
                put(108, &(offset as f32).to_le_bytes());
                put(112, &(self.slope as f32).to_le_bytes());
                put(116, &(self.inter as f32).to_le_bytes());
            } else {
                put(12, &self.datatype.to_le_bytes());
                for (i, d) in self.dim.iter().enumerate() {
                    put(16 + 8 * i, &d.to_le_bytes());
                }
                for (i, p) in self.pixdim.iter().enumerate() {
                    put(104 + 8 * i, &p.to_le_bytes());
                }
                put(168, &(offset as i64).to_le_bytes());
                put(176, &self.slope.to_le_bytes());
                put(184, &self.inter.to_le_bytes());
            }
            let magic = self.magic.unwrap_or(match self.version {
                1 => *b"n+1\0",
                _ => *b"n+2\0",
            });
            h[magic_at..magic_at + 4].copy_from_slice(&magic);
            if self.version == 2 {
                h[8..12].copy_from_slice(b"\r\n\x1a\n");
            }
            h.resize((offset as usize).max(len), 0);
            h.extend_from_slice(data);
            h
        }

        fn write(&self, name: &str, data: &[u8]) -> PathBuf {
            let path = test_path(name);
            std::fs::write(&path, self.bytes(data)).expect("write test file");
            path
        }

        fn write_gz(&self, name: &str, data: &[u8]) -> PathBuf {
            let path = test_path(name);
            std::fs::write(&path, gzip(&self.bytes(data))).expect("write test file");
            path
        }
    }

    fn gzip(data: &[u8]) -> Vec<u8> {
        let mut enc = GzEncoder::new(Vec::new(), flate2::Compression::default());
        enc.write_all(data).expect("compress");
        enc.finish().expect("compress")
    }

    fn load(path: &Path) -> Volume {
        load_nifti(path, NanPolicy::Reject).expect("load")
    }

    fn load_err(path: &Path) -> (DataError, String) {
        let err = load_nifti(path, NanPolicy::Reject).expect_err("should fail");
        let text = err.to_string();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        assert!(text.contains(name), "{text}");
        (err, text)
    }

    fn ramp(n: u8) -> Vec<u8> {
        (0..n).map(|i| i * 3).collect()
    }

    #[test]
    fn little_endian_uint8() {
        let mut nii = Nii::new([3, 2, 4], 2);
        nii.pixdim = [-1.0, 0.5, 2.0, 3.25, 0.0, 0.0, 0.0, 0.0];
        let data = ramp(24);
        let v = load(&nii.write("brain.nii", &data));
        assert_eq!(v.name(), "brain");
        assert_eq!(v.dims(), [3, 2, 4]);
        assert_eq!(v.spacing(), [0.5, 2.0, 3.25]);
        assert_eq!(v.scalar_type(), ScalarType::U8);
        assert_eq!(v.bytes(), &data[..]);
        assert_eq!(v.texel(2, 1, 3), 69.0);
        assert_eq!(v.value_range(), (0.0, 69.0));
    }

    #[test]
    fn big_endian_int16_and_lenient_spacing() {
        let values: Vec<i16> = (0..8).map(|i| i * 1000 - 3500).collect();
        let mut nii = Nii::new([2, 2, 2], 4);
        nii.big = true;
        nii.pixdim = [1.0, 0.0, -2.0, f64::NAN, 0.0, 0.0, 0.0, 0.0];
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
        let v = load(&nii.write("Be16.NII", &data));
        assert_eq!(v.name(), "Be16");
        assert_eq!(v.spacing(), [1.0, 1.0, 1.0]);
        let want: Vec<f32> = values.iter().map(|&x| f32::from(x)).collect();
        assert_eq!(v.samples(), &Samples::F32(want));

        // Big-endian uint16 stays native.
        let values: Vec<u16> = (0..8).map(|i| 0x0102 * (i + 1)).collect();
        let mut nii = Nii::new([2, 2, 2], 512);
        nii.big = true;
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
        let v = load(&nii.write("be_u16.nii", &data));
        assert_eq!(v.samples(), &Samples::U16(values));
    }

    #[test]
    fn converted_types() {
        let cases: [(i16, Vec<u8>, Vec<f32>); 5] = [
            (
                256,
                vec![0x80, 0xFF, 0, 1, 2, 3, 4, 127],
                vec![-128., -1., 0., 1., 2., 3., 4., 127.],
            ),
            (
                8,
                (0..8i32).flat_map(|i| (-i * 100).to_le_bytes()).collect(),
                (0..8).map(|i| (-i * 100) as f32).collect(),
            ),
            (
                768,
                (0..8u32).flat_map(|i| (i * 70000).to_le_bytes()).collect(),
                (0..8).map(|i| (i * 70000) as f32).collect(),
            ),
            (
                16,
                (0..8)
                    .flat_map(|i| (i as f32 * 0.25).to_le_bytes())
                    .collect(),
                (0..8).map(|i| i as f32 * 0.25).collect(),
            ),
            (
                64,
                (0..8)
                    .flat_map(|i| (i as f64 * -1.5).to_le_bytes())
                    .collect(),
                (0..8).map(|i| i as f32 * -1.5).collect(),
            ),
        ];
        for (code, data, want) in cases {
            let v = load(&Nii::new([2, 2, 2], code).write("t.nii", &data));
            assert_eq!(v.samples(), &Samples::F32(want), "datatype {code}");
        }
    }

    #[test]
    fn scl_slope_and_inter() {
        // float32 data, big-endian, scaled by 2 and shifted by -1.
        let mut nii = Nii::new([2, 2, 2], 16);
        nii.big = true;
        nii.slope = 2.0;
        nii.inter = -1.0;
        let data: Vec<u8> = (0..8)
            .flat_map(|i| (i as f32 + 0.5).to_be_bytes())
            .collect();
        let v = load(&nii.write("scaled.nii", &data));
        let want: Vec<f32> = (0..8).map(|i| (i as f32 + 0.5) * 2.0 - 1.0).collect();
        assert_eq!(v.samples(), &Samples::F32(want));

        // Scaled uint8 becomes f32.
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.slope = 0.5;
        nii.inter = 10.0;
        let v = load(&nii.write("scaled8.nii", &[0, 1, 2, 3, 4, 5, 6, 200]));
        assert_eq!(v.scalar_type(), ScalarType::F32);
        assert_eq!(v.value_range(), (10.0, 110.0));
        assert_eq!(v.texel(1, 0, 0), 10.5);

        // Identity and zero slopes keep the native type (slope 0 means "no scaling").
        for (slope, inter) in [(1.0, 0.0), (0.0, 0.0), (0.0, 5.0), (f64::NAN, 3.0)] {
            let mut nii = Nii::new([2, 2, 2], 2);
            nii.slope = slope;
            nii.inter = inter;
            let v = load(&nii.write("plain.nii", &[7; 8]));
            assert_eq!(v.samples(), &Samples::U8(vec![7; 8]), "{slope} {inter}");
        }

        // A slope of 1 with an offset still scales.
        let mut nii = Nii::new([2, 2, 2], 512);
        nii.slope = 1.0;
        nii.inter = -1024.0;
        let data: Vec<u8> = [0u16, 1024, 2048, 0, 0, 0, 0, 0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let v = load(&nii.write("ct.nii", &data));
        assert_eq!(v.scalar_type(), ScalarType::F32);
        assert_eq!(v.texel(0, 1, 0), 1024.0);
        assert_eq!(v.value_range(), (-1024.0, 1024.0));
    }

    #[test]
    fn gzip_files() {
        let values: Vec<u16> = (0..12).map(|i| i * 5000).collect();
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut nii = Nii::new([2, 3, 2], 512);
        nii.pixdim[2] = 0.75;
        let v = load(&nii.write_gz("head.nii.gz", &data));
        assert_eq!(v.name(), "head");
        assert_eq!(v.dims(), [2, 3, 2]);
        assert_eq!(v.spacing(), [1.0, 0.75, 1.0]);
        assert_eq!(v.samples(), &Samples::U16(values.clone()));

        // Compression is found by its magic bytes whatever the name, and an extension block
        // before the data (vox_offset 400) is skipped.
        let mut nii = nii.clone();
        nii.big = true;
        nii.vox_offset = 400.0;
        let be: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
        let v = load(&nii.write_gz("Packed.NII", &be));
        assert_eq!(v.name(), "Packed");
        assert_eq!(v.samples(), &Samples::U16(values.clone()));
        // ...and an uncompressed file named .nii.gz loads as well.
        let v = load(&nii.write("plain.nii.gz", &be));
        assert_eq!(v.name(), "plain");
        assert_eq!(v.samples(), &Samples::U16(values.clone()));

        // Several gzip members (as from concatenated or parallel compressors).
        let bytes = Nii::new([2, 3, 2], 512).bytes(&data);
        let mut members = gzip(&bytes[..300]);
        members.extend(gzip(&bytes[300..]));
        let path = test_path("multi.nii.gz");
        std::fs::write(&path, members).expect("write");
        assert_eq!(load(&path).samples(), &Samples::U16(values));
    }

    #[test]
    fn nifti2() {
        let values: Vec<i32> = (0..8).map(|i| i * -7).collect();
        for big in [false, true] {
            let mut nii = Nii::new([2, 2, 2], 8);
            nii.version = 2;
            nii.big = big;
            nii.pixdim = [1.0, 0.5, 0.25, 4.0, 2.0, 0.0, 0.0, 0.0];
            let data: Vec<u8> = values
                .iter()
                .flat_map(|v| {
                    if big {
                        v.to_be_bytes()
                    } else {
                        v.to_le_bytes()
                    }
                })
                .collect();
            let v = load(&nii.write("two.nii", &data));
            assert_eq!(v.dims(), [2, 2, 2]);
            assert_eq!(v.spacing(), [0.5, 0.25, 4.0]);
            let want: Vec<f32> = values.iter().map(|&x| x as f32).collect();
            assert_eq!(v.samples(), &Samples::F32(want), "big {big}");
        }

        let mut nii = Nii::new([2, 2, 2], 2);
        nii.version = 2;
        nii.dim[0] = 4;
        nii.dim[4] = 1;
        nii.slope = 3.0;
        let v = load(&nii.write_gz("two.nii.gz", &[1; 8]));
        assert_eq!(v.samples(), &Samples::F32(vec![3.0; 8]));

        nii.magic = Some(*b"ni2\0");
        let (_, text) = load_err(&nii.write("pair2.nii", &[1; 8]));
        assert!(text.contains(".hdr/.img"), "{text}");

        let mut nii = Nii::new([2, 2, 2], 2);
        nii.version = 2;
        nii.dim[1] = 1 << 33;
        let (_, text) = load_err(&nii.write("huge2.nii", &[]));
        assert!(text.contains("too large"), "{text}");
    }

    #[test]
    fn four_and_five_dimensions() {
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.dim[0] = 4;
        let v = load(&nii.write("single_frame.nii", &[9; 8]));
        assert_eq!(v.dims(), [2, 2, 2]);
        nii.dim[0] = 5;
        assert_eq!(load(&nii.write("single5.nii", &[9; 8])).dims(), [2, 2, 2]);

        let mut nii = Nii::new([2, 2, 2], 2);
        nii.dim[0] = 4;
        nii.dim[4] = 3;
        let (err, text) = load_err(&nii.write("fmri.nii", &[0; 24]));
        assert!(matches!(err, DataError::Format { .. }), "{err}");
        assert!(
            text.contains("has 3 volumes (dim[4]=3)") && text.contains("only 3-D scalar"),
            "{text}"
        );

        let mut nii = Nii::new([2, 2, 2], 16);
        nii.dim[0] = 5;
        nii.dim[5] = 3;
        let (_, text) = load_err(&nii.write("vectors.nii", &[0; 96]));
        assert!(text.contains("3 components per voxel (dim[5]=3)"), "{text}");

        // A 4th dimension beyond dim[0] is ignored, as the standard says.
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.dim[4] = 7;
        assert_eq!(load(&nii.write("ignored.nii", &[1; 8])).dims(), [2, 2, 2]);

        let mut nii = Nii::new([2, 2, 2], 2);
        nii.dim[0] = 2;
        let (_, text) = load_err(&nii.write("slice.nii", &[0; 8]));
        assert!(text.contains("dim[0]=2"), "{text}");

        let nii = Nii::new([2, 1, 2], 2);
        let (err, text) = load_err(&nii.write("thin.nii", &[0; 4]));
        assert!(matches!(err, DataError::InvalidDims { .. }), "{err}");
        assert!(text.contains("2x1x2"), "{text}");
    }

    #[test]
    fn bad_magic_and_headers() {
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.magic = Some(*b"abcd");
        let (err, text) = load_err(&nii.write("analyze.nii", &[0; 8]));
        assert!(matches!(err, DataError::Format { .. }), "{err}");
        assert!(text.contains("n+1") && text.contains("344"), "{text}");

        nii.magic = Some(*b"ni1\0");
        let (_, text) = load_err(&nii.write("pair.nii", &[0; 8]));
        assert!(text.contains(".hdr/.img"), "{text}");

        let path = test_path("text.nii");
        std::fs::write(&path, b"this is not a volume at all, just words").expect("write");
        let (_, text) = load_err(&path);
        assert!(text.contains("not a NIfTI file"), "{text}");

        let path = test_path("empty.nii");
        std::fs::write(&path, b"").expect("write");
        let (_, text) = load_err(&path);
        assert!(text.contains("not a NIfTI file"), "{text}");

        let bytes = Nii::new([2, 2, 2], 2).bytes(&[0; 8]);
        let path = test_path("stub.nii");
        std::fs::write(&path, &bytes[..200]).expect("write");
        let (err, text) = load_err(&path);
        assert!(matches!(err, DataError::Format { .. }), "{err}");
        assert!(text.contains("truncated") && text.contains("200"), "{text}");

        let mut nii = Nii::new([2, 2, 2], 2);
        nii.vox_offset = 100.0;
        let mut bytes = nii.bytes(&[]);
        bytes.extend([0; 360]);
        let path = test_path("offset.nii");
        std::fs::write(&path, bytes).expect("write");
        let (_, text) = load_err(&path);
        assert!(text.contains("vox_offset 100"), "{text}");

        let (err, _) = load_err(&test_path("absent.nii"));
        assert!(matches!(err, DataError::Io { .. }), "{err}");
    }

    #[test]
    fn unsupported_datatypes() {
        for (code, name) in [
            (32, "complex64"),
            (128, "rgb24"),
            (1024, "int64"),
            (1, "binary"),
            (99, "not a NIfTI type"),
        ] {
            let path = Nii::new([2, 2, 2], code).write("odd.nii", &[0; 128]);
            let (err, text) = load_err(&path);
            assert!(matches!(err, DataError::UnknownType { .. }), "{err}");
            assert!(
                text.contains(name) && text.contains(&format!("datatype {code})")),
                "{text}"
            );
            assert!(text.contains("float32"), "{text}");
        }
    }

    #[test]
    fn truncated_and_corrupt_data() {
        let nii = Nii::new([2, 3, 4], 4);
        let (err, text) = load_err(&nii.write("short.nii", &[0; 40]));
        assert!(
            matches!(
                err,
                DataError::SizeMismatch {
                    expected_bytes: 48,
                    found_bytes: 40,
                    ..
                }
            ),
            "{err}"
        );
        assert!(
            text.contains("truncated") && text.contains("int16"),
            "{text}"
        );

        // Too little data inside a complete gzip stream.
        let (err, text) = load_err(&nii.write_gz("gshort.nii.gz", &[0; 30]));
        assert!(
            matches!(
                err,
                DataError::SizeMismatch {
                    found_bytes: 30,
                    ..
                }
            ),
            "{err}"
        );
        assert!(text.contains("truncated"), "{text}");

        // The stream ends inside the extensions, before vox_offset.
        let mut far = nii.clone();
        far.vox_offset = 4096.0;
        let bytes = far.bytes(&[0; 48]);
        let path = test_path("gext.nii.gz");
        std::fs::write(&path, gzip(&bytes[..1000])).expect("write");
        let (err, _) = load_err(&path);
        assert!(matches!(err, DataError::SizeMismatch { .. }), "{err}");

        // A gzip stream cut off part-way.
        let big = Nii::new([16, 16, 16], 2);
        let data: Vec<u8> = (0..4096u32).map(|i| (i * 7 % 251) as u8).collect();
        let packed = gzip(&big.bytes(&data));
        let path = test_path("gcut.nii.gz");
        std::fs::write(&path, &packed[..packed.len() / 2]).expect("write");
        let (err, text) = load_err(&path);
        assert!(matches!(err, DataError::SizeMismatch { .. }), "{err}");
        assert!(text.contains("truncated"), "{text}");

        // gzip magic followed by garbage.
        let path = test_path("gbad.nii.gz");
        let mut bytes = GZIP_MAGIC.to_vec();
        bytes.extend(b"this is not deflate data, not at all");
        std::fs::write(&path, bytes).expect("write");
        let (err, text) = load_err(&path);
        assert!(matches!(err, DataError::Format { .. }), "{err}");
        assert!(text.contains("corrupt gzip"), "{text}");

        // A valid gzip header with a corrupt deflate body.
        let mut packed = gzip(&big.bytes(&data));
        for b in &mut packed[20..60] {
            *b ^= 0x5a;
        }
        let path = test_path("gflip.nii.gz");
        std::fs::write(&path, packed).expect("write");
        let (err, _) = load_err(&path);
        assert!(
            matches!(
                err,
                DataError::Format { .. } | DataError::SizeMismatch { .. }
            ),
            "{err}"
        );
    }

    #[test]
    fn nan_policy_applies() {
        let mut vals = [2.0f64; 8];
        vals[5] = f64::NAN; // voxel (1, 0, 1)
        let data: Vec<u8> = vals.iter().flat_map(|v| v.to_le_bytes()).collect();
        let path = Nii::new([2, 2, 2], 64).write("nan.nii", &data);
        let (err, text) = load_err(&path);
        assert!(
            matches!(err, DataError::NonFinite { count: 1, .. }),
            "{err}"
        );
        assert!(text.contains("(1, 0, 1)"), "{text}");
        let v = load_nifti(&path, NanPolicy::Replace(-5.0)).expect("replaced");
        assert_eq!(v.texel(1, 0, 1), -5.0);
        assert_eq!(v.value_range(), (-5.0, 2.0));
    }

    #[test]
    fn names() {
        assert_eq!(volume_name(Path::new("/a/b.nii.gz")), "b");
        assert_eq!(volume_name(Path::new("B.NII.GZ")), "B");
        assert_eq!(volume_name(Path::new("c.nii")), "c");
        assert_eq!(volume_name(Path::new("d.gz")), "d");
        assert_eq!(volume_name(Path::new("x.y.nii")), "x.y");
        assert_eq!(volume_name(Path::new(".nii")), "volume");
    }

    /// The Colin 27 ("ch2") template shipped by Debian's mricron-data package.
    #[test]
    fn real_ch2_template() {
        let path = Path::new("/usr/share/mricron/templates/ch2.nii.gz");
        if !path.exists() {
            // Written past the test harness's capture so that the skip is visible.
            let _ = writeln!(
                io::stderr().lock(),
                "skipped: {} not found (install mricron-data)",
                path.display()
            );
            return;
        }
        let v = load(path);
        assert_eq!(v.name(), "ch2");
        assert_eq!(v.dims(), [181, 217, 181]);
        assert_eq!(v.spacing(), [1.0, 1.0, 1.0]);
        assert_eq!(v.scalar_type(), ScalarType::U8);
        let (lo, hi) = v.value_range();
        assert!(hi - lo >= 100.0, "value range {lo}..{hi}");
        // A head in a dark background: the corner is background, a good part is tissue.
        assert_eq!(v.texel(0, 0, 0), lo);
        let Samples::U8(s) = v.samples() else {
            panic!("uint8 expected");
        };
        let bright = s
            .iter()
            .filter(|&&x| f32::from(x) > lo + 0.25 * (hi - lo))
            .count();
        assert!(
            bright > s.len() / 20 && bright < s.len() * 3 / 4,
            "{bright}"
        );
    }
}
