//! Decoding of VTK XML binary streams: a block header followed by the data, base64-encoded
//! or raw, optionally split into zlib-compressed blocks.
//!
//! Every size in a header is checked against the size the array needs before anything is
//! allocated or decompressed, and no block may inflate to more than zlib can produce from
//! its compressed size, so a forged header cannot make the reader allocate more than a
//! small multiple of the file.

use std::io::Read;

use flate2::read::ZlibDecoder;

/// File-wide settings from the `<VTKFile>` element.
#[derive(Clone, Copy)]
pub(crate) struct Layout {
    pub big_endian: bool,
    /// Size of the block headers: 4 (`UInt32`) or 8 (`UInt64`).
    pub header_size: usize,
    pub compressed: bool,
}

/// The most bytes deflate can produce per compressed byte (its limit is 1032:1).
const MAX_INFLATION: usize = 1032;

/// A VTK XML number type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DataType {
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Float32,
    Float64,
}

impl DataType {
    /// The type of a `type="…"` attribute; VTK's older names (`Int`, `Float`, …) too.
    pub fn from_name(name: &str) -> Option<DataType> {
        Some(match name {
            "Int8" | "Char" => DataType::Int8,
            "UInt8" | "UnsignedChar" => DataType::UInt8,
            "Int16" | "Short" => DataType::Int16,
            "UInt16" | "UnsignedShort" => DataType::UInt16,
            "Int32" | "Int" => DataType::Int32,
            "UInt32" | "UnsignedInt" => DataType::UInt32,
            "Int64" | "Long" | "LongLong" | "IdType" => DataType::Int64,
            "UInt64" | "UnsignedLong" | "UnsignedLongLong" => DataType::UInt64,
            "Float32" | "Float" => DataType::Float32,
            "Float64" | "Double" => DataType::Float64,
            _ => return None,
        })
    }

    pub fn size(self) -> usize {
        match self {
            DataType::Int8 | DataType::UInt8 => 1,
            DataType::Int16 | DataType::UInt16 => 2,
            DataType::Int32 | DataType::UInt32 | DataType::Float32 => 4,
            DataType::Int64 | DataType::UInt64 | DataType::Float64 => 8,
        }
    }

    /// One value from its `size()` bytes.
    pub fn value(self, bytes: &[u8], big_endian: bool) -> f64 {
        let mut b = [0u8; 8];
        let size = self.size();
        b[..size].copy_from_slice(&bytes[..size]);
        if big_endian {
            b[..size].reverse();
        }
        let bits = u64::from_le_bytes(b);
        let shift = 64 - 8 * size as u32;
        match self {
            DataType::Float32 => f64::from(f32::from_bits(bits as u32)),
            DataType::Float64 => f64::from_bits(bits),
            DataType::UInt8 | DataType::UInt16 | DataType::UInt32 | DataType::UInt64 => bits as f64,
            _ => ((bits << shift) as i64 >> shift) as f64,
        }
    }

    /// Every value of `bytes` (a whole number of values).
    pub fn values(self, bytes: &[u8], big_endian: bool) -> Vec<f64> {
        bytes
            .chunks_exact(self.size())
            .map(|c| self.value(c, big_endian))
            .collect()
    }
}

/// Where a binary stream lies: raw bytes (appended raw data) or base64 text (inline
/// `binary` arrays and appended base64 data), which is decoded only as far as needed.
#[derive(Clone, Copy)]
pub(crate) enum Stream<'a> {
    Raw(&'a [u8]),
    Base64(&'a [u8]),
}

impl Stream<'_> {
    /// The most bytes the stream can hold.
    fn capacity(&self) -> usize {
        match self {
            Stream::Raw(bytes) => bytes.len(),
            Stream::Base64(text) => text.len() / 4 * 3 + 3,
        }
    }

    /// The first `n` bytes of the stream, or an error saying it is shorter.
    fn prefix(&self, n: usize, what: &str) -> Result<Vec<u8>, String> {
        let bytes = match self {
            Stream::Raw(bytes) => bytes.get(..n).map(<[u8]>::to_vec),
            Stream::Base64(text) => {
                let decoded = base64_decode(text, n)?;
                (decoded.len() >= n).then(|| decoded[..n].to_vec())
            }
        };
        bytes.ok_or_else(|| format!("data is truncated: the file ends inside the {what}"))
    }
}

fn b64_value(c: u8) -> Option<u32> {
    Some(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => return None,
    } as u32)
}

/// Decodes base64 quantum by quantum (so separately padded pieces may follow each other)
/// until at least `need` bytes are out, the text ends or a `<` is met.
pub(crate) fn base64_decode(text: &[u8], need: usize) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(need.min(text.len() / 4 * 3 + 3));
    let mut quad = [0u8; 4];
    let mut n = 0;
    for (at, &c) in text.iter().enumerate() {
        if out.len() >= need || c == b'<' {
            break;
        }
        if c.is_ascii_whitespace() {
            continue;
        }
        quad[n] = c;
        n += 1;
        if n == 4 {
            n = 0;
            let pads = quad.iter().rev().take_while(|&&c| c == b'=').count();
            if pads > 2 {
                return Err(format!(
                    "invalid base64: {:?} near character {at} is padding only",
                    String::from_utf8_lossy(&quad)
                ));
            }
            let mut bits = 0u32;
            for &q in &quad[..4 - pads] {
                bits = bits << 6
                    | b64_value(q)
                        .ok_or_else(|| format!("invalid base64 character {:?}", q as char))?;
            }
            bits <<= 6 * pads as u32;
            out.extend_from_slice(&bits.to_be_bytes()[1..4 - pads]);
        }
    }
    Ok(out)
}

/// Reads header word `i` of `bytes`.
fn word(bytes: &[u8], i: usize, layout: Layout) -> Result<usize, String> {
    let h = layout.header_size;
    let b = bytes
        .get(i * h..(i + 1) * h)
        .ok_or("data ends inside the block header")?;
    let mut v = 0u64;
    for k in 0..h {
        let byte = if layout.big_endian {
            b[k]
        } else {
            b[h - 1 - k]
        };
        v = v << 8 | u64::from(byte);
    }
    usize::try_from(v).map_err(|_| format!("block size {v} is too large"))
}

/// The `need` data bytes of a binary stream (block header and data). Every size the header
/// states is checked against `need`, the file's length and zlib's inflation limit before
/// anything is allocated.
pub(crate) fn read_stream(stream: Stream, layout: Layout, need: usize) -> Result<Vec<u8>, String> {
    let h = layout.header_size;
    if !layout.compressed {
        let head = stream.prefix(h, "block header")?;
        let n = word(&head, 0, layout)?;
        if n != need {
            return Err(announced(n, need));
        }
        if n > stream.capacity().saturating_sub(h) {
            return Err(format!(
                "data is truncated: the header announces {n} bytes, the file holds fewer"
            ));
        }
        let mut bytes = stream.prefix(h + n, "data")?;
        return Ok(bytes.split_off(h));
    }
    let head = stream.prefix(3 * h, "block header")?;
    let blocks = word(&head, 0, layout)?;
    let block_size = word(&head, 1, layout)?;
    let last = word(&head, 2, layout)?;
    let last = if last == 0 { block_size } else { last };
    let total = match blocks {
        0 => Some(0),
        _ => (blocks - 1)
            .checked_mul(block_size)
            .and_then(|t| t.checked_add(last)),
    };
    if total != Some(need) {
        return Err(match total {
            Some(total) => announced(total, need),
            None => format!(
                "the block header announces {blocks} blocks of {block_size} bytes: too many"
            ),
        });
    }
    let header = blocks
        .checked_add(3)
        .and_then(|b| b.checked_mul(h))
        .filter(|&len| len <= stream.capacity())
        .ok_or_else(|| format!("the header announces {blocks} blocks, more than the file holds"))?;
    let head = stream.prefix(header, "block header")?;
    let sizes = (0..blocks)
        .map(|b| word(&head, 3 + b, layout))
        .collect::<Result<Vec<_>, _>>()?;
    let end = sizes
        .iter()
        .try_fold(header, |at, &size| at.checked_add(size))
        .filter(|&end| end <= stream.capacity())
        .ok_or("data is truncated: the compressed blocks run past the end of the file")?;
    let expected = |b: usize| if b + 1 == blocks { last } else { block_size };
    if let Some((b, &size)) = sizes
        .iter()
        .enumerate()
        .find(|&(b, &size)| expected(b) > size.saturating_mul(MAX_INFLATION))
    {
        return Err(format!(
            "zlib block {b} would inflate {size} bytes to {}, more than zlib can",
            expected(b)
        ));
    }
    let bytes = stream.prefix(end, "compressed blocks")?;
    let mut out = Vec::with_capacity(need);
    let mut at = header;
    for (b, &size) in sizes.iter().enumerate() {
        let expect = expected(b);
        let before = out.len();
        ZlibDecoder::new(&bytes[at..at + size])
            .take(expect as u64 + 1)
            .read_to_end(&mut out)
            .map_err(|e| format!("corrupt zlib block {b}: {e}"))?;
        if out.len() - before != expect {
            return Err(format!(
                "zlib block {b} holds {} bytes, the header announces {expect}",
                out.len() - before
            ));
        }
        at += size;
    }
    Ok(out)
}

fn announced(found: usize, need: usize) -> String {
    format!("the block header announces {found} bytes of data, the array needs {need}")
}
