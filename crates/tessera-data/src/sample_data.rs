//! Reading the sample data of a volume file, shared by the raw, NRRD and NIfTI loaders, with
//! the type conversions described in [`crate::raw`].
//!
//! A header can claim any size. Files are checked against their length before reading; a
//! stream (decompressed data) cannot be, so its buffers grow as bytes arrive and a header
//! that lies costs no more memory than the data that came with it.

use std::io::{self, Read};
use std::path::Path;

use bytemuck::Pod;
use rayon::prelude::*;

use crate::error::{DataError, Result};
use crate::input::sample_bytes;
use crate::raw::{Endian, SourceType};
use crate::volume::Samples;

/// The first buffer of a stream holds this many bytes; each further one doubles it.
const FIRST_STREAM_CHUNK: usize = 1 << 20;

/// Whether the input is known to hold the bytes the header describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Supply {
    /// The file's length was checked: buffers are allocated at their final size at once,
    /// so multi-gigabyte files cost no reallocation.
    Checked,
    /// A stream that may end early: buffers grow while reading.
    Stream,
}

/// Number of samples of a `dims` grid, refusing sizes this machine cannot address.
pub(crate) fn sample_count(path: &Path, dims: [u32; 3]) -> Result<usize> {
    dims.iter()
        .try_fold(1usize, |acc, &d| acc.checked_mul(d as usize))
        .filter(|n| n.checked_mul(8).is_some())
        .ok_or_else(|| DataError::format(path, format!("dimensions {dims:?} are too large")))
}

/// Reads `count` samples of `source` type and converts them as described in [`crate::raw`].
/// A short read is a [`DataError::SizeMismatch`]; a count whose bytes exceed
/// [`crate::input::MAX_SAMPLE_BYTES`] is refused before anything is allocated.
pub(crate) fn read_samples(
    reader: &mut impl Read,
    count: usize,
    source: SourceType,
    endian: Endian,
    supply: Supply,
    path: &Path,
) -> Result<Samples> {
    let need = sample_bytes(path, count as u64, source)?;
    let swap = match endian {
        Endian::Little => cfg!(target_endian = "big"),
        Endian::Big => cfg!(target_endian = "little"),
    };
    let truncated = |found: u64| DataError::SizeMismatch {
        path: path.to_path_buf(),
        expected_bytes: need,
        found_bytes: found,
        detail: format!("sample data for {count} {} samples", source.name()),
    };
    let read_err = |e| DataError::io(path, e);
    let samples = match source {
        SourceType::U8 => {
            let v: Vec<u8> = read_values(reader, count, supply)
                .map_err(read_err)?
                .map_err(truncated)?;
            Samples::U8(v)
        }
        SourceType::U16 => {
            let mut v: Vec<u16> = read_values(reader, count, supply)
                .map_err(read_err)?
                .map_err(truncated)?;
            if swap {
                v.par_iter_mut().for_each(|x| *x = x.swap_bytes());
            }
            Samples::U16(v)
        }
        SourceType::U32 | SourceType::I32 | SourceType::F32 => {
            // The buffer holds file bits until the pass below turns them into values.
            let mut v: Vec<f32> = read_values(reader, count, supply)
                .map_err(read_err)?
                .map_err(truncated)?;
            v.par_iter_mut().for_each(|x| {
                let bits = if swap {
                    x.to_bits().swap_bytes()
                } else {
                    x.to_bits()
                };
                *x = match source {
                    SourceType::U32 => bits as f32,
                    SourceType::I32 => bits as i32 as f32,
                    _ => f32::from_bits(bits),
                };
            });
            Samples::F32(v)
        }
        SourceType::I8 | SourceType::I16 | SourceType::F64 => {
            let size = source.size_bytes();
            // `sample_bytes` bounded `need`, so it fits a usize.
            let bytes: Vec<u8> = read_values(reader, need as usize, supply)
                .map_err(read_err)?
                .map_err(truncated)?;
            let big = endian == Endian::Big;
            let v: Vec<f32> = bytes
                .par_chunks_exact(size)
                .map(|c| match source {
                    SourceType::I8 => c[0] as i8 as f32,
                    SourceType::I16 => {
                        let b = [c[0], c[1]];
                        let x = if big {
                            i16::from_be_bytes(b)
                        } else {
                            i16::from_le_bytes(b)
                        };
                        x as f32
                    }
                    _ => {
                        let mut b = [0u8; 8];
                        b.copy_from_slice(c);
                        let x = if big {
                            f64::from_be_bytes(b)
                        } else {
                            f64::from_le_bytes(b)
                        };
                        x as f32
                    }
                })
                .collect();
            Samples::F32(v)
        }
    };
    Ok(samples)
}

/// `count` values of `T` in file bytes, or `Err(bytes)` with the number of bytes there were
/// when the input ended early. With [`Supply::Stream`] the buffer starts small and doubles.
pub(crate) fn read_values<T: Pod>(
    reader: &mut impl Read,
    count: usize,
    supply: Supply,
) -> io::Result<std::result::Result<Vec<T>, u64>> {
    let size = std::mem::size_of::<T>();
    let mut target = match supply {
        Supply::Checked => count,
        Supply::Stream => count.min(FIRST_STREAM_CHUNK / size),
    };
    let mut values: Vec<T> = Vec::new();
    loop {
        let start = values.len();
        values.resize(target, T::zeroed());
        let buf: &mut [u8] = bytemuck::cast_slice_mut(&mut values[start..]);
        let got = fill(reader, buf)?;
        if got < buf.len() {
            return Ok(Err((start * size + got) as u64));
        }
        if target == count {
            return Ok(Ok(values));
        }
        target = count.min(target.saturating_mul(2));
    }
}

/// Discards up to `n` bytes; returns how many there were.
pub(crate) fn skip(reader: &mut impl Read, n: u64) -> io::Result<u64> {
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

/// An error of reading a gzip stream, where an I/O error that says the data is invalid
/// means the compressed data is corrupt.
pub(crate) fn in_gzip(error: DataError) -> DataError {
    match error {
        DataError::Io { path, error }
            if matches!(
                error.kind(),
                io::ErrorKind::InvalidData | io::ErrorKind::InvalidInput
            ) =>
        {
            DataError::format(&path, format!("corrupt gzip data: {error}"))
        }
        other => other,
    }
}

/// Reads until `buf` is full or the input ends; returns the number of bytes read. A stream
/// that ends mid-way (e.g. a cut gzip member) counts as ending, so the caller can report how
/// much data there was.
pub(crate) fn fill(reader: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match reader.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => break,
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

#[cfg(test)]
#[path = "sample_data_tests.rs"]
mod tests;
