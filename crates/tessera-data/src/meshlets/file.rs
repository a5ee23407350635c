//! The meshlet file `tessera extract --meshlets` writes: a [`MeshletMesh`] as it lies on the
//! GPU, so a renderer or a notebook can load it without extracting again.
//!
//! Layout (all little-endian, no padding):
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `TSMSHLT1` |
//! | 4 | `u32` meshlet record size in bytes (44) |
//! | 4 | `u32` meshlet count `M` |
//! | 4 | `u32` vertex count `V` |
//! | 4 | `u32` triangle count `T` |
//! | 4 | `f32` isovalue, in the volume's sample units |
//! | 4 | `u32` flags: bit 0 set when positions are physical (spacing and placement applied), clear for grid units |
//! | 44·M | meshlets ([`Meshlet`]): `u32` vertex offset, triangle offset, counts (vertices in bits 0–15, triangles in bits 16–31); `f32` AABB min xyz, max xyz; `u32` subblock minimum cell x \| y << 16, then z \| size x << 16 \| size y << 20 \| size z << 24 |
//! | 12·V | `f32` positions xyz |
//! | 12·V | `f32` normals xyz |
//! | 3·T | `u8` local indices, three per triangle, into the meshlet's vertex range |
//!
//! In numpy: `np.frombuffer(data, np.uint32, 11 * M, 32).reshape(M, 11)` for the records
//! (columns 3–8 viewed as `float32`), then positions, normals and indices at the offsets the
//! table gives.

use std::io::{self, Write};

use crate::error::{DataError, Result};
use crate::meshlets::format::{Meshlet, MeshletMesh};

const MAGIC: &[u8; 8] = b"TSMSHLT1";
const HEADER_BYTES: usize = 32;
/// Size of one meshlet record: eleven 4-byte words.
pub const MESHLET_RECORD_BYTES: usize = std::mem::size_of::<Meshlet>();
const _: () = assert!(MESHLET_RECORD_BYTES == 44);
const FLAG_PHYSICAL: u32 = 1;

/// Where a meshlet file's positions live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshletUnits {
    /// Sample-index coordinates of the volume.
    Grid,
    /// Physical units: the volume's spacing and placement applied.
    Physical,
}

/// A meshlet file's contents.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshletFile {
    pub mesh: MeshletMesh,
    pub isovalue: f32,
    pub units: MeshletUnits,
}

fn count(n: usize, what: &str) -> io::Result<u32> {
    u32::try_from(n).map_err(|_| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{n} {what} do not fit a meshlet file"),
        )
    })
}

/// Writes `file` in the layout above.
pub fn write_meshlet_file(file: &MeshletFile, w: &mut impl Write) -> io::Result<()> {
    let mesh = &file.mesh;
    let mut header = Vec::with_capacity(HEADER_BYTES);
    header.extend_from_slice(MAGIC);
    let flags = match file.units {
        MeshletUnits::Grid => 0,
        MeshletUnits::Physical => FLAG_PHYSICAL,
    };
    for word in [
        MESHLET_RECORD_BYTES as u32,
        count(mesh.meshlets.len(), "meshlets")?,
        count(mesh.positions.len(), "vertices")?,
        count(mesh.triangle_count(), "triangles")?,
        file.isovalue.to_bits(),
        flags,
    ] {
        header.extend_from_slice(&word.to_le_bytes());
    }
    w.write_all(&header)?;
    let words: &[u32] = bytemuck::cast_slice(&mesh.meshlets);
    write_words(w, words.iter().copied())?;
    write_words(w, mesh.positions.iter().flatten().map(|v| v.to_bits()))?;
    write_words(w, mesh.normals.iter().flatten().map(|v| v.to_bits()))?;
    w.write_all(&mesh.local_indices)
}

/// Writes 4-byte words little-endian, staged so an unbuffered writer is not called per word.
fn write_words(w: &mut impl Write, words: impl Iterator<Item = u32>) -> io::Result<()> {
    let mut buf = Vec::with_capacity(1 << 16);
    for word in words {
        buf.extend_from_slice(&word.to_le_bytes());
        if buf.len() >= 1 << 16 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

/// Reads a meshlet file's bytes; `path` names the file in errors. Ranges, limits and local
/// indices are checked ([`MeshletMesh::validate_structure`]) before the mesh is returned, so
/// no consumer indexes outside its arrays.
pub fn read_meshlet_file(path: &std::path::Path, bytes: &[u8]) -> Result<MeshletFile> {
    let bad = |message: String| DataError::Format {
        path: path.to_path_buf(),
        message,
    };
    if bytes.len() < HEADER_BYTES || &bytes[..8] != MAGIC {
        return Err(bad("not a Tessera meshlet file (no TSMSHLT1 magic)".into()));
    }
    let word = |i: usize| {
        let at = 8 + 4 * i;
        u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
    };
    let record = word(0) as usize;
    if record != MESHLET_RECORD_BYTES {
        return Err(bad(format!(
            "meshlet records of {record} bytes; this reader knows {MESHLET_RECORD_BYTES}"
        )));
    }
    let [meshlets, vertices, triangles] = [word(1), word(2), word(3)].map(|n| n as u64);
    let isovalue = f32::from_bits(word(4));
    let units = match word(5) {
        0 => MeshletUnits::Grid,
        FLAG_PHYSICAL => MeshletUnits::Physical,
        other => return Err(bad(format!("unknown flags {other:#x}"))),
    };
    let sizes = [
        meshlets * record as u64,
        vertices * 12,
        vertices * 12,
        triangles * 3,
    ];
    let expected = HEADER_BYTES as u64 + sizes.iter().sum::<u64>();
    if bytes.len() as u64 != expected {
        return Err(DataError::SizeMismatch {
            path: path.to_path_buf(),
            expected_bytes: expected,
            found_bytes: bytes.len() as u64,
            detail: format!(
                "{meshlets} meshlets, {vertices} vertices and {triangles} triangles as the \
                 header says"
            ),
        });
    }
    let mut at = HEADER_BYTES;
    let mut take = |n: u64| {
        let part = &bytes[at..at + n as usize];
        at += n as usize;
        part
    };
    let words = |part: &[u8]| -> Vec<u32> {
        part.chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    let vectors = |part: &[u8]| -> Vec<[f32; 3]> {
        words(part)
            .chunks_exact(3)
            .map(|v| [v[0], v[1], v[2]].map(f32::from_bits))
            .collect()
    };
    let meshlet_words = words(take(sizes[0]));
    let mesh = MeshletMesh {
        meshlets: bytemuck::cast_slice::<u32, Meshlet>(&meshlet_words).to_vec(),
        positions: vectors(take(sizes[1])),
        normals: vectors(take(sizes[2])),
        local_indices: take(sizes[3]).to_vec(),
    };
    mesh.validate_structure().map_err(|e| bad(e.to_string()))?;
    Ok(MeshletFile {
        mesh,
        isovalue,
        units,
    })
}
