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
//! dimension equal to 1 (time series and vector data are refused). [`load_nifti_components`]
//! takes the further dimensions as values per voxel, and also volumes of one voxel or slice.
//!
//! Read from the header: `dim`, `datatype`, `pixdim[1..=3]` (the spacing), `vox_offset`,
//! `scl_slope`/`scl_inter`, and the placement (see [`crate::Orientation`]): the sform when
//! `sform_code` > 0, else the qform (quaternion, offsets and `qfac` = `pixdim[0]`) when
//! `qform_code` > 0, else none; both name RAS world space. Samples stay in file order (i
//! fastest, then j, then k). Ignored: units, intent codes, `cal_min`/`cal_max`; extensions
//! are skipped by starting at `vox_offset`.
//!
//! Deliberate leniencies: a spacing that is zero, negative or not finite means 1 (many files
//! leave `pixdim` at 0); a `vox_offset` of 0 means the data follows the header and its 4-byte
//! extension flag; bytes after the data are ignored.

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use flate2::bufread::MultiGzDecoder;
use rayon::prelude::*;

use crate::error::{DataError, Result};
use crate::input::{open_regular, sample_bytes};
use crate::orientation::Orientation;
use crate::raw::{Endian, SourceType};
use crate::sample_data::{fill, in_gzip, read_samples, sample_count, skip, Supply};
use crate::volume::{NanPolicy, Samples, Volume};

#[path = "nifti_orientation.rs"]
mod orientation;

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
    /// Values per voxel: the product of dim[4..] (1 for scalar volumes).
    components: u32,
    spacing: [f32; 3],
    orientation: Orientation,
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
    qform_code: i32,
    sform_code: i32,
    /// Quaternion parameters b, c, d (a follows from them).
    quatern: [f64; 3],
    qoffset: [f64; 3],
    /// The first three rows of the sform affine.
    srow: [[f64; 4]; 3],
}

/// Loads a single-file NIfTI-1 or NIfTI-2 volume, gzip-compressed or not. See the module
/// documentation for type conversion, intensity scaling and what is ignored.
pub fn load_nifti(path: &Path, nan_policy: NanPolicy) -> Result<Volume> {
    scalar_volume(open_nifti(path, false)?, path, nan_policy)
}

/// A NIfTI file held in memory, as [`load_nifti`] reads it from disk; `path` names it in
/// errors and gives the volume its name.
pub fn parse_bytes(bytes: &[u8], path: &Path, nan_policy: NanPolicy) -> Result<Volume> {
    scalar_volume(decode_bytes(bytes, path, false)?, path, nan_policy)
}

fn scalar_volume(
    (header, samples): (Header, Samples),
    path: &Path,
    nan_policy: NanPolicy,
) -> Result<Volume> {
    let volume = Volume::with_nan_policy(
        volume_name(path),
        header.dims,
        header.spacing,
        samples,
        nan_policy,
    )
    .map_err(|e| e.in_file(path))?;
    Ok(volume.with_orientation(header.orientation))
}

/// A volume of several values per voxel (e.g. SH coefficients): component `c` of voxel
/// `(x, y, z)` is `values[((c * nz + z) * ny + y) * nx + x]`, NIfTI's own order.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentVolume {
    pub dims: [u32; 3],
    pub spacing: [f32; 3],
    /// The grid's placement from the qform or sform, as for a scalar volume.
    pub orientation: Orientation,
    pub components: u32,
    pub values: Vec<f32>,
}

impl ComponentVolume {
    /// The components of voxel `(x, y, z)`.
    pub fn voxel(&self, x: u32, y: u32, z: u32) -> Vec<f32> {
        let [nx, ny, nz] = self.dims.map(|d| d as usize);
        let at = (z as usize * ny + y as usize) * nx + x as usize;
        (0..self.components as usize)
            .map(|c| self.values[c * nx * ny * nz + at])
            .collect()
    }

    /// The grid axis towards the patient's head ([`Orientation::up_axis`]).
    pub fn up_axis(&self) -> Option<(usize, i8)> {
        self.orientation.up_axis()
    }
}

/// Loads a NIfTI file whose dimensions past the third hold several values per voxel; values
/// are converted to `f32` (with the header's scaling). Non-finite values are errors naming the
/// file.
pub fn load_nifti_components(path: &Path) -> Result<ComponentVolume> {
    component_volume(open_nifti(path, true)?, path)
}

/// A file of several values per voxel held in memory, as [`load_nifti_components`] reads it
/// from disk; `path` names it in errors.
pub fn parse_components_bytes(bytes: &[u8], path: &Path) -> Result<ComponentVolume> {
    component_volume(decode_bytes(bytes, path, true)?, path)
}

fn component_volume((header, samples): (Header, Samples), path: &Path) -> Result<ComponentVolume> {
    let values: Vec<f32> = match samples {
        Samples::U8(v) => v.into_iter().map(f32::from).collect(),
        Samples::U16(v) => v.into_iter().map(f32::from).collect(),
        Samples::F32(v) => v,
    };
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(DataError::format(
            path,
            format!("value {i} is not finite ({})", values[i]),
        ));
    }
    Ok(ComponentVolume {
        dims: header.dims,
        spacing: header.spacing,
        orientation: header.orientation,
        components: header.components,
        values,
    })
}

/// Header and (scaled) samples of a single-file NIfTI, gzip-compressed or not.
fn open_nifti(path: &Path, components: bool) -> Result<(Header, Samples)> {
    let io_err = |e| DataError::io(path, e);
    let mut file = open_regular(path)?;
    let mut magic = [0u8; 2];
    let got = fill(&mut file, &mut magic).map_err(io_err)?;
    file.seek(SeekFrom::Start(0)).map_err(io_err)?;
    let len = file.metadata().map_err(io_err)?.len();
    let gzip = got == magic.len() && magic == GZIP_MAGIC;
    decode(BufReader::new(file), gzip, len, path, components)
}

fn decode_bytes(bytes: &[u8], path: &Path, components: bool) -> Result<(Header, Samples)> {
    let gzip = bytes.starts_with(&GZIP_MAGIC);
    decode(bytes, gzip, bytes.len() as u64, path, components)
}

/// Header and (scaled) samples from `input`, `len` bytes long (compressed, if `gzip`).
fn decode(
    mut input: impl BufRead,
    gzip: bool,
    len: u64,
    path: &Path,
    components: bool,
) -> Result<(Header, Samples)> {
    let (header, samples) = if gzip {
        let mut decoder = MultiGzDecoder::new(input);
        read_nifti(&mut decoder, path, None, components).map_err(in_gzip)?
    } else {
        read_nifti(&mut input, path, Some(len), components)?
    };
    let samples = match header.scaling {
        Some((slope, inter)) => rescale(samples, slope, inter),
        None => samples,
    };
    Ok((header, samples))
}

/// Reads header and samples from the (decompressed) stream. `file_len` is the size of an
/// uncompressed file, which lets a short file be reported before anything is allocated.
fn read_nifti(
    reader: &mut impl Read,
    path: &Path,
    file_len: Option<u64>,
    components: bool,
) -> Result<(Header, Samples)> {
    let header = read_header(reader, path, components)?;
    let count = sample_count(path, header.dims)?
        .checked_mul(header.components as usize)
        .ok_or_else(|| DataError::format(path, "too many values".to_string()))?;
    let need = sample_bytes(path, count as u64, header.source)?;
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
    // Only the length of an uncompressed file could be checked.
    let supply = match file_len {
        Some(_) => Supply::Checked,
        None => Supply::Stream,
    };
    let samples = read_samples(reader, count, header.source, header.endian, supply, path).map_err(
        |e| match e {
            DataError::SizeMismatch { found_bytes, .. } => truncated(found_bytes),
            other => other,
        },
    )?;
    Ok((header, samples))
}

/// Reads the NIfTI-1 or NIfTI-2 header, leaving `reader` just after it.
fn read_header(reader: &mut impl Read, path: &Path, components: bool) -> Result<Header> {
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
    validate(raw, len as u64, endian, path, components)
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
        qform_code: i32::from(f.i16(252)),
        sform_code: i32::from(f.i16(254)),
        quatern: std::array::from_fn(|i| f64::from(f.f32(256 + 4 * i))),
        qoffset: std::array::from_fn(|i| f64::from(f.f32(268 + 4 * i))),
        srow: std::array::from_fn(|r| {
            std::array::from_fn(|c| f64::from(f.f32(280 + 16 * r + 4 * c)))
        }),
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
        qform_code: f.i32(344),
        sform_code: f.i32(348),
        quatern: std::array::from_fn(|i| f.f64(352 + 8 * i)),
        qoffset: std::array::from_fn(|i| f.f64(376 + 8 * i)),
        srow: std::array::from_fn(|r| std::array::from_fn(|c| f.f64(400 + 32 * r + 8 * c))),
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

fn validate(
    raw: RawHeader,
    header_len: u64,
    endian: Endian,
    path: &Path,
    allow_components: bool,
) -> Result<Header> {
    let fail = |msg: String| DataError::format(path, msg);
    let dim = raw.dim;
    let ndim = dim[0];
    if !(3..=7).contains(&ndim) {
        return Err(fail(format!(
            "dim[0]={ndim}: only 3-D scalar volumes are supported (dim[0]=3, or 4..7 with \
             dim[4..] all 1)"
        )));
    }
    let mut components = 1u32;
    for (i, &d) in dim.iter().enumerate().take(ndim as usize + 1).skip(4) {
        if allow_components && d >= 1 {
            components = u32::try_from(d)
                .ok()
                .and_then(|d| components.checked_mul(d))
                .ok_or_else(|| fail(format!("dim[{i}]={d} is too large")))?;
            continue;
        }
        if d != 1 {
            let what = match i {
                4 => format!("has {d} volumes (dim[4]={d})"),
                5 => format!("has {d} components per voxel (dim[5]={d})"),
                _ => format!("has dim[{i}]={d}"),
            };
            return Err(fail(format!(
                "{what}; only 3-D scalar volumes are supported here (SH coefficient volumes \
                 render as glyphs with sh:FILE)"
            )));
        }
    }
    // A coefficient volume of one slice or one voxel still holds glyphs; a scalar volume
    // needs cells to interpolate in.
    if allow_components && dim[1..4].iter().any(|&d| d < 1) {
        return Err(fail(format!(
            "invalid dimensions {}x{}x{}: a coefficient volume needs at least 1 voxel along \
             every axis",
            dim[1], dim[2], dim[3]
        )));
    }
    if !allow_components && dim[1..4].iter().any(|&d| d < 2) {
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

    let orientation = orientation::placement(&raw);
    Ok(Header {
        header_len,
        endian,
        source,
        dims,
        components,
        spacing,
        orientation,
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

    fn i32(&self, at: usize) -> i32 {
        i32::from_le_bytes(self.take(at))
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
#[path = "nifti_tests.rs"]
mod tests;
