//! Numbers of a Gmsh file, as text tokens (ASCII files) or fixed-size binary values
//! (binary files), so that the section readers serve both.

use std::str::FromStr;

use super::super::text::Cursor;
use crate::error::{DataError, Result};

/// How binary values are stored.
#[derive(Clone, Copy)]
pub(super) struct Binary {
    pub big_endian: bool,
    /// Bytes of a `size_t` (the header's data-size: 4 or 8).
    pub size_t: usize,
}

pub(super) struct Numbers<'a> {
    pub cur: Cursor<'a>,
    pub binary: Option<Binary>,
}

impl Numbers<'_> {
    /// An error at the current place: its line in ASCII files, its byte offset in binary.
    pub fn err(&self, message: impl std::fmt::Display) -> DataError {
        match self.binary {
            Some(_) => self.cur.err_at_byte(self.cur.offset(), message),
            None => self.cur.err(message),
        }
    }

    fn fixed(&mut self, size: usize, what: &str) -> Result<u64> {
        let at = self.cur.offset();
        let big_endian = self.binary.is_some_and(|b| b.big_endian);
        let bytes = self
            .cur
            .bytes(size, what)
            .map_err(|_| self.cur.err_at_byte(at, format!("file ends inside {what}")))?;
        let mut v = 0u64;
        for k in 0..size {
            let byte = if big_endian {
                bytes[k]
            } else {
                bytes[size - 1 - k]
            };
            v = v << 8 | u64::from(byte);
        }
        Ok(v)
    }

    fn text<T: FromStr>(&mut self, what: &str) -> Result<T> {
        self.cur.parse(what)
    }

    /// A C `int` (4 bytes in binary files).
    pub fn int(&mut self, what: &str) -> Result<i64> {
        match self.binary {
            Some(_) => Ok(i64::from(self.fixed(4, what)? as u32 as i32)),
            None => self.text(what),
        }
    }

    /// A `size_t` (the header's data-size in binary files).
    pub fn size(&mut self, what: &str) -> Result<u64> {
        match self.binary {
            Some(b) => self.fixed(b.size_t, what),
            None => self.text(what),
        }
    }

    pub fn double(&mut self, what: &str) -> Result<f64> {
        match self.binary {
            Some(_) => Ok(f64::from_bits(self.fixed(8, what)?)),
            None => self.text(what),
        }
    }

    /// A count of items that each take at least `min_bytes` in the file (one byte in ASCII
    /// files, where each is at least a digit), refused when the rest of the file cannot hold
    /// that many, so that nothing is allocated for a count the file does not back.
    pub fn count(&mut self, what: &str, min_bytes: usize, value: u64) -> Result<usize> {
        let per = if self.binary.is_some() { min_bytes } else { 1 };
        let left = self.cur.remaining();
        usize::try_from(value)
            .ok()
            .filter(|&n| n.saturating_mul(per) <= left)
            .ok_or_else(|| {
                self.err(format!(
                    "{what} is {value}, more than the {left} bytes left in the file can hold"
                ))
            })
    }

    /// A non-negative `int` that fits `u32` (entity tags, element types).
    pub fn small(&mut self, what: &str) -> Result<u32> {
        let v = self.int(what)?;
        u32::try_from(v).map_err(|_| self.err(format!("{what} {v} is out of range")))
    }
}
