//! Reading back the meshes [`TriangleMesh::write_ply`] and [`TriangleMesh::write_obj`] write
//! (and the common cases other tools write: PLY with float vertex properties and a face list,
//! OBJ with `v`, `vn` and triangular `f` lines), so exports can be checked and reused.
//! Anything else is refused with the file and the reason, never guessed at.

use std::path::Path;

use glam::Vec3;

use crate::error::{DataError, Result};
use crate::mesh::{MeshFormat, TriangleMesh};

/// Reads a mesh file, its format chosen by the extension.
pub fn read_mesh_file(path: &Path) -> Result<TriangleMesh> {
    let format = MeshFormat::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|error| DataError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    let parsed = match format {
        MeshFormat::Ply => read_ply(&bytes),
        MeshFormat::Obj => read_obj(&String::from_utf8_lossy(&bytes)),
    };
    parsed.map_err(|message| DataError::Format {
        path: path.to_path_buf(),
        message,
    })
}

/// A PLY file of `float` vertex properties (`x y z`, optionally `nx ny nz`) and one face list
/// property of triangles, ASCII or binary little-endian.
pub fn read_ply(bytes: &[u8]) -> std::result::Result<TriangleMesh, String> {
    let end = find(bytes, b"end_header\n").ok_or("no 'end_header' line")?;
    let header = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not text")?;
    let layout = PlyLayout::parse(header)?;
    let body = &bytes[end + b"end_header\n".len()..];
    match layout.encoding {
        PlyEncoding::Ascii => layout.read_ascii(&String::from_utf8_lossy(body)),
        PlyEncoding::BinaryLittleEndian => layout.read_binary(body),
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[derive(Debug, PartialEq)]
enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
}

/// Widths in bytes of the integer types a face list may use.
fn int_width(name: &str) -> Option<usize> {
    match name {
        "uchar" | "uint8" | "char" | "int8" => Some(1),
        "ushort" | "uint16" | "short" | "int16" => Some(2),
        "uint" | "uint32" | "int" | "int32" => Some(4),
        _ => None,
    }
}

struct PlyLayout {
    encoding: PlyEncoding,
    vertices: usize,
    /// Names of the vertex properties, all `float`.
    vertex_properties: Vec<String>,
    faces: usize,
    /// Byte widths of the face list's count and indices.
    count_width: usize,
    index_width: usize,
}

impl PlyLayout {
    fn parse(header: &str) -> std::result::Result<PlyLayout, String> {
        let mut lines = header.lines();
        if lines.next().map(str::trim) != Some("ply") {
            return Err("not a PLY file (no 'ply' line)".into());
        }
        let mut layout = PlyLayout {
            encoding: PlyEncoding::Ascii,
            vertices: 0,
            vertex_properties: Vec::new(),
            faces: 0,
            count_width: 1,
            index_width: 4,
        };
        let mut element = "";
        for line in lines {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["format", "ascii", _] => layout.encoding = PlyEncoding::Ascii,
                ["format", "binary_little_endian", _] => {
                    layout.encoding = PlyEncoding::BinaryLittleEndian
                }
                ["format", other, ..] => return Err(format!("PLY format '{other}' is not read")),
                ["comment", ..] | ["obj_info", ..] | [] => {}
                ["element", name, count] => {
                    let count: usize = count
                        .parse()
                        .map_err(|_| format!("element {name}: count '{count}'"))?;
                    element = match *name {
                        "vertex" => {
                            layout.vertices = count;
                            "vertex"
                        }
                        "face" => {
                            layout.faces = count;
                            "face"
                        }
                        other => return Err(format!("element '{other}' is not read")),
                    };
                }
                ["property", "float" | "float32", name] if element == "vertex" => {
                    layout.vertex_properties.push(name.to_string())
                }
                ["property", "list", count, index, _] if element == "face" => {
                    layout.count_width =
                        int_width(count).ok_or(format!("face list count type '{count}'"))?;
                    layout.index_width =
                        int_width(index).ok_or(format!("face list index type '{index}'"))?;
                }
                _ => return Err(format!("header line '{line}' is not read")),
            }
        }
        for axis in ["x", "y", "z"] {
            if !layout.vertex_properties.iter().any(|p| p == axis) {
                return Err(format!("vertices have no float property '{axis}'"));
            }
        }
        Ok(layout)
    }

    fn column(&self, name: &str) -> Option<usize> {
        self.vertex_properties.iter().position(|p| p == name)
    }

    /// Builds the mesh from each vertex's property values and each face's index list.
    fn assemble(
        &self,
        vertex_values: &[f32],
        faces: Vec<Vec<u64>>,
    ) -> std::result::Result<TriangleMesh, String> {
        let stride = self.vertex_properties.len();
        let pick = |names: [&str; 3]| -> Option<Vec<Vec3>> {
            let columns = names.map(|n| self.column(n));
            let [Some(a), Some(b), Some(c)] = columns else {
                return None;
            };
            Some(
                vertex_values
                    .chunks_exact(stride)
                    .map(|v| Vec3::new(v[a], v[b], v[c]))
                    .collect(),
            )
        };
        let positions = pick(["x", "y", "z"]).unwrap_or_default();
        let normals = pick(["nx", "ny", "nz"]).unwrap_or_default();
        let triangles = faces
            .into_iter()
            .enumerate()
            .map(|(f, list)| triangle(f, &list, positions.len()))
            .collect::<std::result::Result<_, _>>()?;
        Ok(TriangleMesh {
            positions,
            normals,
            triangles,
        })
    }

    fn read_ascii(&self, body: &str) -> std::result::Result<TriangleMesh, String> {
        let mut words = body.split_whitespace();
        let mut next = |what: &str| words.next().ok_or(format!("the file ends inside {what}"));
        let mut values = Vec::with_capacity(self.vertices * self.vertex_properties.len());
        for v in 0..self.vertices {
            for _ in &self.vertex_properties {
                let word = next("the vertices")?;
                values.push(
                    word.parse::<f32>()
                        .map_err(|_| format!("vertex {v}: '{word}' is not a number"))?,
                );
            }
        }
        let mut faces = Vec::with_capacity(self.faces);
        for f in 0..self.faces {
            let parse = |word: &str| {
                word.parse::<u64>()
                    .map_err(|_| format!("face {f}: '{word}' is not an index"))
            };
            let count = parse(next("the faces")?)?;
            let list = (0..count)
                .map(|_| parse(next("the faces")?))
                .collect::<std::result::Result<Vec<_>, _>>()?;
            faces.push(list);
        }
        self.assemble(&values, faces)
    }

    fn read_binary(&self, body: &[u8]) -> std::result::Result<TriangleMesh, String> {
        let vertex_bytes = self
            .vertices
            .checked_mul(4 * self.vertex_properties.len())
            .filter(|&n| n <= body.len())
            .ok_or(format!(
                "{} bytes cannot hold {} vertices",
                body.len(),
                self.vertices
            ))?;
        let values: Vec<f32> = body[..vertex_bytes]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let mut at = vertex_bytes;
        let mut read_int = |width: usize, f: usize| -> std::result::Result<u64, String> {
            let bytes = body
                .get(at..at + width)
                .ok_or(format!("the file ends inside face {f}"))?;
            at += width;
            let mut le = [0u8; 8];
            le[..width].copy_from_slice(bytes);
            Ok(u64::from_le_bytes(le))
        };
        let mut faces = Vec::with_capacity(self.faces.min(body.len()));
        for f in 0..self.faces {
            let count = read_int(self.count_width, f)?;
            let list = (0..count)
                .map(|_| read_int(self.index_width, f))
                .collect::<std::result::Result<Vec<_>, _>>()?;
            faces.push(list);
        }
        self.assemble(&values, faces)
    }
}

/// Face `f`'s indices as a triangle of a mesh of `vertices` vertices.
fn triangle(f: usize, list: &[u64], vertices: usize) -> std::result::Result<[u32; 3], String> {
    let [a, b, c] = list else {
        return Err(format!(
            "face {f} has {} corners; only triangles are read",
            list.len()
        ));
    };
    let check = |i: u64| {
        u32::try_from(i)
            .ok()
            .filter(|&i| (i as usize) < vertices)
            .ok_or(format!("face {f}: index {i} of {vertices} vertices"))
    };
    Ok([check(*a)?, check(*b)?, check(*c)?])
}

/// An OBJ of `v x y z`, optional `vn` lines (one per `v`, as [`TriangleMesh::write_obj`]
/// writes them) and triangular `f` lines (`a`, `a/t`, `a//n` or `a/t/n`, 1-based or
/// negative). Other lines (groups, materials, texture coordinates) are skipped.
pub fn read_obj(text: &str) -> std::result::Result<TriangleMesh, String> {
    let mut mesh = TriangleMesh::default();
    // (line, corners, vertices read before the line): negative indices count back from there.
    let mut faces: Vec<(usize, [i64; 3], usize)> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line_no = n + 1;
        let mut words = line.split_whitespace();
        let vector = |words: std::str::SplitWhitespace| -> std::result::Result<Vec3, String> {
            let v: Vec<f32> = words
                .map(str::parse)
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| format!("line {line_no}: '{line}' has a non-number"))?;
            match v.as_slice() {
                [x, y, z] | [x, y, z, _] => Ok(Vec3::new(*x, *y, *z)),
                _ => Err(format!("line {line_no}: '{line}' is not three numbers")),
            }
        };
        match words.next() {
            Some("v") => mesh.positions.push(vector(words)?),
            Some("vn") => mesh.normals.push(vector(words)?),
            Some("f") => {
                let corners: Vec<i64> = words
                    .map(|w| w.split('/').next().unwrap_or("").parse::<i64>())
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| format!("line {line_no}: '{line}' has a bad index"))?;
                let [a, b, c] = corners[..] else {
                    return Err(format!(
                        "line {line_no}: a face of {} corners; only triangles are read",
                        corners.len()
                    ));
                };
                faces.push((line_no, [a, b, c], mesh.positions.len()));
            }
            _ => {}
        }
    }
    let count = mesh.positions.len();
    for (line_no, corners, read_before) in faces {
        let resolve = |i: i64| -> std::result::Result<u32, String> {
            // OBJ counts from 1; negative indices count back from the last vertex read.
            let zero_based = if i > 0 { i - 1 } else { read_before as i64 + i };
            u32::try_from(zero_based)
                .ok()
                .filter(|&z| (z as usize) < count)
                .ok_or(format!("line {line_no}: index {i} of {count} vertices"))
        };
        mesh.triangles.push([
            resolve(corners[0])?,
            resolve(corners[1])?,
            resolve(corners[2])?,
        ]);
    }
    if !mesh.normals.is_empty() && mesh.normals.len() != count {
        return Err(format!(
            "{} normals for {count} vertices: only one normal per vertex is read",
            mesh.normals.len()
        ));
    }
    Ok(mesh)
}
