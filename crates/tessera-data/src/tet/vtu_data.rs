//! Decoding of VTK XML `DataArray` contents: ASCII, inline base64 `binary`, and appended
//! raw or base64 data, each optionally split into zlib-compressed blocks.

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

/// Size in bytes of a VTK XML type name, `None` for unknown names.
pub(crate) fn type_size(ty: &str) -> Option<usize> {
    Some(match ty {
        "Int8" | "UInt8" => 1,
        "Int16" | "UInt16" => 2,
        "Int32" | "UInt32" | "Float32" => 4,
        "Int64" | "UInt64" | "Float64" => 8,
        _ => return None,
    })
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
    let mut out = Vec::with_capacity(need.min(1 << 28));
    let mut quad = [0u8; 4];
    let mut n = 0;
    for &c in text {
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
    usize::try_from(v).map_err(|_| "block size too large".to_string())
}

/// How many bytes of a binary stream starting at a header are needed to hold everything,
/// given its first bytes (used to decode only the needed base64 prefix).
pub(crate) fn needed_bytes(head: &[u8], layout: Layout) -> Result<usize, String> {
    let h = layout.header_size;
    if !layout.compressed {
        return Ok(h + word(head, 0, layout)?);
    }
    let blocks = word(head, 0, layout)?;
    let header = h * (3 + blocks);
    if head.len() < header {
        return Ok(header);
    }
    let sizes: usize = (0..blocks)
        .map(|b| word(head, 3 + b, layout))
        .sum::<Result<_, _>>()?;
    Ok(header + sizes)
}

/// Unpacks a binary stream (header + data, compressed or not) into its data bytes.
pub(crate) fn unpack(bytes: &[u8], layout: Layout) -> Result<Vec<u8>, String> {
    let h = layout.header_size;
    if !layout.compressed {
        let n = word(bytes, 0, layout)?;
        let data = bytes.get(h..h + n).ok_or_else(|| {
            format!(
                "data is truncated: header announces {n} bytes, {} present",
                bytes.len().saturating_sub(h)
            )
        })?;
        return Ok(data.to_vec());
    }
    let blocks = word(bytes, 0, layout)?;
    let block_size = word(bytes, 1, layout)?;
    let last = word(bytes, 2, layout)?;
    let mut at = h * (3 + blocks);
    let mut out = Vec::new();
    for b in 0..blocks {
        let size = word(bytes, 3 + b, layout)?;
        let chunk = bytes
            .get(at..at + size)
            .ok_or_else(|| format!("compressed block {b} is truncated"))?;
        let expect = if b + 1 == blocks && last != 0 {
            last
        } else {
            block_size
        };
        let before = out.len();
        ZlibDecoder::new(chunk)
            .take(expect as u64 + 1)
            .read_to_end(&mut out)
            .map_err(|e| format!("corrupt zlib block {b}: {e}"))?;
        if out.len() - before != expect {
            return Err(format!(
                "zlib block {b} holds {} bytes, expected {expect}",
                out.len() - before
            ));
        }
        at += size;
    }
    Ok(out)
}

/// Converts raw array bytes of type `ty` to numbers.
pub(crate) fn convert(bytes: &[u8], ty: &str, big_endian: bool) -> Result<Vec<f64>, String> {
    let size = type_size(ty).ok_or_else(|| format!("unsupported type {ty:?}"))?;
    if !bytes.len().is_multiple_of(size) {
        return Err(format!(
            "{} bytes is not a whole number of {ty} values",
            bytes.len()
        ));
    }
    Ok(bytes
        .chunks_exact(size)
        .map(|c| {
            let mut b = [0u8; 8];
            if big_endian {
                b[..size].copy_from_slice(c);
                b[..size].reverse();
            } else {
                b[..size].copy_from_slice(c);
            }
            let bits = u64::from_le_bytes(b);
            let shift = 64 - 8 * size as u32;
            match ty {
                "Float32" => f64::from(f32::from_bits(bits as u32)),
                "Float64" => f64::from_bits(bits),
                t if t.starts_with('U') => bits as f64,
                _ => ((bits << shift) as i64 >> shift) as f64,
            }
        })
        .collect())
}
