//! Opening the files a user names, and the limit on how much sample data a header may ask
//! for.
//!
//! Only regular files are read. A named pipe blocks until someone writes to it and a device
//! such as `/dev/zero` never ends, so both are refused before anything opens them for reading.

use std::fs::{File, Metadata};
use std::path::Path;

use crate::error::{DataError, Result};
use crate::raw::SourceType;

/// Most bytes of sample data one file may describe (64 GiB). Larger than any volume a GPU of
/// today holds, small enough that a header's size is refused before memory runs out.
pub const MAX_SAMPLE_BYTES: u64 = 64 << 30;

/// The metadata of `path` if it is a regular file (symbolic links followed); a clear error
/// naming the file otherwise.
pub(crate) fn regular_file(path: &Path) -> Result<Metadata> {
    let meta = std::fs::metadata(path).map_err(|e| DataError::io(path, e))?;
    if meta.is_file() {
        return Ok(meta);
    }
    let what = file_kind(&meta);
    Err(DataError::format(
        path,
        format!("is {what}, not a regular file: only regular files can be loaded"),
    ))
}

/// Opens `path` for reading after checking that it is a regular file.
pub(crate) fn open_regular(path: &Path) -> Result<File> {
    regular_file(path)?;
    File::open(path).map_err(|e| DataError::io(path, e))
}

/// Bytes of `count` samples of `source`, refusing sizes that overflow or exceed
/// [`MAX_SAMPLE_BYTES`].
pub(crate) fn sample_bytes(path: &Path, count: u64, source: SourceType) -> Result<u64> {
    count
        .checked_mul(source.size_bytes() as u64)
        .filter(|&bytes| bytes <= MAX_SAMPLE_BYTES)
        .ok_or_else(|| {
            DataError::format(
                path,
                format!(
                    "the header describes {count} {} samples, more than the {} GiB of sample \
                     data a file may hold",
                    source.name(),
                    MAX_SAMPLE_BYTES >> 30
                ),
            )
        })
}

#[cfg(unix)]
fn file_kind(meta: &Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let kind = meta.file_type();
    if kind.is_dir() {
        "a directory"
    } else if kind.is_fifo() {
        "a named pipe (FIFO)"
    } else if kind.is_char_device() {
        "a character device"
    } else if kind.is_block_device() {
        "a block device"
    } else if kind.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn file_kind(meta: &Metadata) -> &'static str {
    if meta.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

#[cfg(test)]
#[path = "input_tests.rs"]
mod tests;
