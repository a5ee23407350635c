//! NRRD volumes (`.nrrd` with attached data, `.nhdr` with detached data), raw or gzip
//! encoded. Sample types are converted as for raw files: `uint8`/`uint16` stay native,
//! everything else becomes `f32` (see [`crate::raw`]).
//!
//! Deliberate leniencies: a missing `endian` field means little-endian, NaN `spacings`
//! entries mean 1, and bytes after the expected data are ignored (readers take exactly the
//! bytes the header describes).
//!
//! Placement: the lengths of the `space directions` vectors are the spacing, their directions
//! and `space origin` the volume's [`crate::Orientation`], and `space` (RAS, LAS, LPS) its
//! anatomical space. Without `space directions` the spacing comes from `spacings` and the
//! orientation is the default.

use std::io::{BufRead, BufReader, Cursor, Seek, SeekFrom};
use std::path::Path;

use flate2::bufread::MultiGzDecoder;

use crate::error::{DataError, Result};
use crate::input::{open_regular, sample_bytes};
use crate::sample_data::{in_gzip, read_samples, sample_count, skip, Supply};
use crate::volume::{NanPolicy, Samples, Volume};

#[path = "nrrd_header.rs"]
mod header;

use header::{parse_header, Encoding, Header};

/// Loads a NRRD file; detached data files are resolved relative to the header's directory.
/// Header and data files must be regular files.
pub fn load_nrrd(path: &Path, nan_policy: NanPolicy) -> Result<Volume> {
    let mut reader = BufReader::new(open_regular(path)?);
    let header = parse_header(&mut reader, path)?;
    let samples = match &header.data_file {
        Some(name) => {
            let data_path = path.parent().unwrap_or(Path::new(".")).join(name);
            let file = open_regular(&data_path)
                .map_err(|e| e.labelled(format!("{}: data file", path.display())))?;
            read_data(&mut BufReader::new(file), &header, &data_path, path)?
        }
        None => read_data(&mut reader, &header, path, path)?,
    };
    into_volume(header, samples, path, nan_policy)
}

/// A NRRD with attached data held in memory, as [`load_nrrd`] reads it from a file; `path`
/// names it in errors and gives the volume its name. Headers naming a detached data file are
/// refused.
pub fn parse_bytes(bytes: &[u8], path: &Path, nan_policy: NanPolicy) -> Result<Volume> {
    let mut reader = Cursor::new(bytes);
    let header = parse_header(&mut reader, path)?;
    if header.data_file.is_some() {
        let msg = "names a detached data file, which only a NRRD on disk can have";
        return Err(DataError::format(path, msg));
    }
    let samples = read_data(&mut reader, &header, path, path)?;
    into_volume(header, samples, path, nan_policy)
}

fn into_volume(header: Header, samples: Samples, path: &Path, policy: NanPolicy) -> Result<Volume> {
    let name = path
        .file_stem()
        .map_or_else(|| "volume".into(), |s| s.to_string_lossy().into_owned());
    let volume = Volume::with_nan_policy(name, header.dims, header.spacing, samples, policy)
        .map_err(|e| e.in_file(path))?;
    Ok(volume.with_orientation(header.orientation))
}

/// The samples `header` (from `header_path`) describes, read from `reader`, which is at the
/// end of an attached header or the start of a data file (`data_path`).
fn read_data(
    reader: &mut (impl BufRead + Seek),
    header: &Header,
    data_path: &Path,
    header_path: &Path,
) -> Result<Samples> {
    let io_err = |e| DataError::io(data_path, e);
    skip_lines(reader, header.line_skip, data_path)?;
    let count = sample_count(header_path, header.dims)?;
    let need = sample_bytes(header_path, count as u64, header.source)?;
    let truncated = |found: u64, what: &str| DataError::SizeMismatch {
        path: data_path.to_path_buf(),
        expected_bytes: need,
        found_bytes: found,
        detail: format!("{what} described by {}", header_path.display()),
    };
    let (source, endian) = (header.source, header.endian);
    match header.encoding {
        Encoding::Raw => {
            let pos = reader.stream_position().map_err(io_err)?;
            let len = reader.seek(SeekFrom::End(0)).map_err(io_err)?;
            let start = if header.byte_skip < 0 {
                // "byte skip: -1": the data is the last bytes of the file.
                len.checked_sub(need)
                    .filter(|s| *s >= pos)
                    .ok_or_else(|| truncated(len.saturating_sub(pos), "raw data"))?
            } else {
                pos.saturating_add(header.byte_skip as u64)
            };
            let available = len.saturating_sub(start);
            if available < need {
                return Err(truncated(available, "raw data"));
            }
            reader.seek(SeekFrom::Start(start)).map_err(io_err)?;
            read_samples(reader, count, source, endian, Supply::Checked, data_path)
        }
        Encoding::Gzip => {
            let mut decoder = MultiGzDecoder::new(reader);
            // For compressed data the skip counts decompressed bytes.
            let skip_bytes = header.byte_skip as u64;
            let skipped =
                skip(&mut decoder, skip_bytes).map_err(|e| in_gzip(DataError::io(data_path, e)))?;
            if skipped < skip_bytes {
                return Err(truncated(0, "gzip data (ended inside the byte skip)"));
            }
            read_samples(
                &mut decoder,
                count,
                source,
                endian,
                Supply::Stream,
                data_path,
            )
            .map_err(in_gzip)
        }
    }
}

/// Skips the header's `line skip` lines, failing where the data ends (a count of 2^63 must
/// not spin at the end of the file).
fn skip_lines(reader: &mut impl BufRead, lines: u64, data_path: &Path) -> Result<()> {
    for done in 0..lines {
        let skipped = reader
            .skip_until(b'\n')
            .map_err(|e| DataError::io(data_path, e))?;
        if skipped == 0 {
            let msg = format!("line skip {lines}: the data ends after {done} line(s)");
            return Err(DataError::format(data_path, msg));
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "nrrd_tests.rs"]
mod tests;
