//! Gmsh `.msh` files: format 4.1 and 2.2, ASCII or binary (either byte order).
//! Element type 4 (4-node tet) is kept and type 11 (10-node tet) keeps its corners; every
//! other element type is skipped and counted. The elementary entity of each tet becomes its
//! region (the entity tag of its block in 4.1, the second tag of the element in 2.2, or the
//! first when it has only one); the first one-component `$NodeData` becomes the vertex
//! scalar (nodes it leaves out get NaN). Other sections are skipped: their end marker is
//! looked for line by line, which binary sections such as 4.1's `$Entities` also pass.

mod numbers;
mod v2;
mod v4;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use numbers::{Binary, Numbers};

use super::text::{field, Cursor};
use super::{finish, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};

/// Gmsh element types that become tets.
pub const MSH_TET4: u32 = 4;
pub const MSH_TET10: u32 = 11;

/// Mesh format versions read.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Version {
    V2,
    V4,
}

/// Loads a Gmsh mesh (format 4.1 or 2.2, ASCII or binary).
pub fn load_msh(path: &Path) -> Result<(TetMesh, MeshReport)> {
    parse_bytes(&read_file(path)?, path)
}

/// Parses the bytes of a Gmsh mesh; `path` names the file in errors.
pub fn parse_bytes(bytes: &[u8], path: &Path) -> Result<(TetMesh, MeshReport)> {
    let mut n = Numbers {
        cur: Cursor::new(bytes, path, None),
        binary: None,
    };
    let mut version = None;
    let mut mesh = Builder::default();
    let mut scalars: Option<(String, Vec<f32>)> = None;
    while let Some((line, fields)) = n.cur.record() {
        let section = fields[0];
        if !section.starts_with('$') {
            return Err(n.cur.err_at(
                line,
                format!("expected a section such as $Nodes, found {section:?}"),
            ));
        }
        if version.is_none() && section != "$MeshFormat" {
            return Err(n.cur.err_at(
                line,
                "not a Gmsh mesh: the file must start with $MeshFormat",
            ));
        }
        match (section, version) {
            ("$MeshFormat", _) => version = Some(mesh_format(&mut n)?),
            ("$Nodes", Some(Version::V4)) => v4::nodes(&mut n, &mut mesh)?,
            ("$Nodes", Some(Version::V2)) => v2::nodes(&mut n, &mut mesh)?,
            ("$Elements", Some(Version::V4)) => v4::elements(&mut n, &mut mesh)?,
            ("$Elements", Some(Version::V2)) => v2::elements(&mut n, &mut mesh)?,
            ("$NodeData", _) if scalars.is_none() => scalars = node_data(&mut n, &mesh)?,
            _ => {}
        }
        let end = format!("$End{}", &section[1..]);
        loop {
            let (_, f) = n
                .cur
                .record()
                .ok_or_else(|| n.cur.err(format!("file ends before {end}")))?;
            if f[0] == end {
                break;
            }
        }
    }
    if version.is_none() {
        return Err(DataError::format(
            path,
            "not a Gmsh mesh: no $MeshFormat section",
        ));
    }
    let mut out = TetMesh::new(mesh.vertices, mesh.tets);
    out.regions = Some(mesh.regions);
    if let Some((name, values)) = scalars {
        out.scalars = Some(values);
        out.scalar_name = name;
    }
    finish(out, path, mesh.skipped)
}

/// Reads the `$MeshFormat` line (and, in binary files, the byte-order word after it).
fn mesh_format(n: &mut Numbers) -> Result<Version> {
    let (line, f) = n
        .cur
        .record()
        .ok_or_else(|| n.cur.err("file ends inside $MeshFormat"))?;
    let version = f[0];
    let file_type: u32 = field(&n.cur, line, &f, 1, "the file type (0 = ASCII, 1 = binary)")?;
    let data_size: usize = field(&n.cur, line, &f, 2, "the data size")?;
    let v = match version {
        v if v.starts_with("4.1") => Version::V4,
        v if v.starts_with("2.") => Version::V2,
        _ => {
            return Err(n.cur.err_at(
                line,
                format!(
                    "msh format {version} is not supported: save the mesh as version 4.1 or 2.2"
                ),
            ))
        }
    };
    match file_type {
        0 => {}
        1 => {
            if data_size != 4 && data_size != 8 {
                return Err(n.cur.err_at(
                    line,
                    format!("data size {data_size}: expected 8 (or 4), the size of size_t"),
                ));
            }
            let at = n.cur.offset();
            let one = n.cur.bytes(4, "the byte-order word")?;
            let big_endian = match one {
                [1, 0, 0, 0] => false,
                [0, 0, 0, 1] => true,
                _ => {
                    return Err(n.cur.err_at_byte(
                        at,
                        format!(
                            "expected the binary word 1 that tells the byte order, found {one:?}"
                        ),
                    ))
                }
            };
            n.binary = Some(Binary {
                big_endian,
                size_t: data_size,
            });
        }
        other => {
            return Err(n.cur.err_at(
                line,
                format!("file type {other}: expected 0 (ASCII) or 1 (binary)"),
            ))
        }
    }
    Ok(v)
}

/// Nodes and tets as the section readers find them.
#[derive(Default)]
struct Builder {
    vertices: Vec<[f32; 3]>,
    tag_index: HashMap<u64, u32>,
    tets: Vec<[u32; 4]>,
    regions: Vec<u32>,
    skipped: usize,
}

impl Builder {
    fn node(&mut self, tag: u64, p: [f64; 3]) -> std::result::Result<(), String> {
        let index = self.vertices.len() as u32;
        if self.tag_index.insert(tag, index).is_some() {
            return Err(format!("node tag {tag} defined twice"));
        }
        self.vertices.push(p.map(|c| c as f32));
        Ok(())
    }

    /// Takes one element of Gmsh type `kind` (its node tags): tets are kept, other types
    /// skipped.
    fn element(
        &mut self,
        element: u64,
        kind: u32,
        region: u32,
        nodes: &[u64],
    ) -> std::result::Result<(), String> {
        let Some(want) = tet_nodes(kind) else {
            self.skipped += 1;
            return Ok(());
        };
        if nodes.len() != want {
            return Err(format!(
                "element {element} of type {kind} has {} node tags, expected {want}",
                nodes.len()
            ));
        }
        let mut tet = [0u32; 4];
        for (slot, tag) in tet.iter_mut().zip(nodes) {
            *slot = *self.tag_index.get(tag).ok_or_else(|| {
                format!(
                    "tet {} (element {element}): node tag {tag} out of range (not defined in $Nodes)",
                    self.tets.len()
                )
            })?;
        }
        self.tets.push(tet);
        self.regions.push(region);
        Ok(())
    }
}

/// Nodes of the tet element types.
fn tet_nodes(kind: u32) -> Option<usize> {
    match kind {
        MSH_TET4 => Some(4),
        MSH_TET10 => Some(10),
        _ => None,
    }
}

/// Nodes of a Gmsh element type, which binary files leave the reader to know.
fn element_nodes(kind: u32) -> Option<usize> {
    Some(match kind {
        15 => 1,
        1 => 2,
        2 | 8 => 3,
        3 | 4 | 26 => 4,
        7 | 27 => 5,
        6 | 9 | 28 => 6,
        5 | 16 => 8,
        10 | 20 => 9,
        11 | 21 => 10,
        22 => 12,
        19 => 13,
        14 => 14,
        18 | 23 | 24 => 15,
        13 => 18,
        17 | 29 => 20,
        25 => 21,
        12 => 27,
        30 => 35,
        31 => 56,
        92 => 64,
        93 => 125,
        _ => return None,
    })
}

/// Node count of `kind` for a binary reader, or an error naming the type.
fn binary_element_nodes(n: &Numbers, kind: u32) -> Result<usize> {
    element_nodes(kind).ok_or_else(|| {
        n.err(format!(
            "element type {kind} is unknown, so its size in this binary file is unknown"
        ))
    })
}

fn tag_lines(cur: &mut Cursor, n: usize, what: &str) -> Result<Vec<String>> {
    let mut lines = Vec::with_capacity(n.min(64));
    for _ in 0..n {
        match cur.record() {
            Some((_, f)) => lines.push(f.join(" ")),
            None => return Err(cur.err(format!("file ends inside $NodeData ({what})"))),
        }
    }
    Ok(lines)
}

fn tag_count(cur: &mut Cursor, what: &str) -> Result<usize> {
    let text = tag_lines(cur, 1, what)?.remove(0);
    text.parse()
        .map_err(|_| cur.err(format!("expected {what}, found {text:?}")))
}

type NodeData = Option<(String, Vec<f32>)>;

/// A `$NodeData` section (the same in 2.2 and 4.1): its tags are text lines in every file,
/// its entries text lines or binary `int` node tags each followed by `double` values.
fn node_data(n: &mut Numbers, mesh: &Builder) -> Result<NodeData> {
    let cur = &mut n.cur;
    let n_str = tag_count(cur, "the string tag count")?;
    let strings = tag_lines(cur, n_str, "string tags")?;
    let n_real = tag_count(cur, "the real tag count")?;
    tag_lines(cur, n_real, "real tags")?;
    let n_int = tag_count(cur, "the integer tag count")?;
    let ints = tag_lines(cur, n_int, "integer tags")?;
    let ncomp: usize = ints.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let entries: u64 = ints.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
    let name = strings
        .first()
        .map_or("node_data".to_string(), |s| s.trim_matches('"').to_string());
    let entry_bytes = 4usize.saturating_add(ncomp.saturating_mul(8));
    let entries = n.count("the $NodeData entry count", entry_bytes, entries)?;
    let mut values = vec![f32::NAN; mesh.vertices.len()];
    for _ in 0..entries {
        let (tag, value) = match n.binary {
            Some(_) => {
                // A 4-byte int in 4.1 too: Gmsh and meshio write it so, although the 4.1
                // format description says size_t.
                let tag = n.int("a node tag")?;
                let mut first = 0.0;
                for c in 0..ncomp {
                    let v = n.double("a value")?;
                    if c == 0 {
                        first = v;
                    }
                }
                (u64::try_from(tag).unwrap_or(u64::MAX), first)
            }
            None => {
                let (line, f) = n
                    .cur
                    .record()
                    .ok_or_else(|| n.cur.err("file ends inside $NodeData"))?;
                if ncomp != 1 {
                    continue;
                }
                let tag: u64 = field(&n.cur, line, &f, 0, "a node tag")?;
                (tag, field(&n.cur, line, &f, 1, "a value")?)
            }
        };
        if ncomp != 1 {
            continue;
        }
        let index = mesh
            .tag_index
            .get(&tag)
            .ok_or_else(|| n.err(format!("$NodeData names unknown node tag {tag}")))?;
        values[*index as usize] = value as f32;
    }
    Ok((ncomp == 1).then_some((name, values)))
}

/// Writes a Gmsh 4.1 ASCII mesh: one node block, one element block per run of tets with
/// the same region (the entity tag; 1 without regions), and the vertex scalars as
/// `$NodeData`. Absorption colours are not written.
pub fn write_msh41(mesh: &TetMesh, path: &Path) -> Result<()> {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    let n = mesh.vertices.len();
    let _ = writeln!(s, "$Nodes\n1 {n} 1 {n}\n3 1 0 {n}");
    (1..=n).for_each(|t| {
        let _ = writeln!(s, "{t}");
    });
    for p in &mesh.vertices {
        let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
    }
    s.push_str("$EndNodes\n");
    let region = |t: usize| mesh.regions.as_ref().map_or(1, |r| r[t]);
    let mut runs = Vec::new();
    for t in 0..mesh.tets.len() {
        if t == 0 || region(t) != region(t - 1) {
            runs.push((t, t + 1));
        } else {
            runs.last_mut().expect("started").1 = t + 1;
        }
    }
    let m = mesh.tets.len();
    let _ = writeln!(s, "$Elements\n{} {m} 1 {m}", runs.len());
    for (start, end) in runs {
        let _ = writeln!(s, "3 {} {MSH_TET4} {}", region(start), end - start);
        for t in start..end {
            let v = mesh.tets[t];
            let _ = writeln!(
                s,
                "{} {} {} {} {}",
                t + 1,
                v[0] + 1,
                v[1] + 1,
                v[2] + 1,
                v[3] + 1
            );
        }
    }
    s.push_str("$EndElements\n");
    if let Some(values) = &mesh.scalars {
        let name = mesh.scalar_name.replace('"', "'");
        let _ = writeln!(s, "$NodeData\n1\n\"{name}\"\n1\n0.0\n3\n0\n1\n{n}");
        for (i, v) in values.iter().enumerate() {
            let _ = writeln!(s, "{} {v}", i + 1);
        }
        s.push_str("$EndNodeData\n");
    }
    write_file(path, s.as_bytes())
}

#[cfg(test)]
mod tests;
