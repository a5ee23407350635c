//! Legacy VTK files (`.vtk`), `DATASET UNSTRUCTURED_GRID`, ASCII or BINARY (big-endian),
//! with the classic `CELLS n size` layout or the 5.1 `OFFSETS`/`CONNECTIVITY` one.
//!
//! Tetrahedra (cell type 10) are kept, quadratic tetrahedra (24) keep their corners, every
//! other cell type is skipped and counted. The first one-component `SCALARS` of `POINT_DATA`
//! becomes the vertex scalar; in `CELL_DATA` a three-component `SCALARS absorption` becomes
//! the absorption colour and the first integral one-component `SCALARS` the region.
//! Other attributes (`VECTORS`, `FIELD`, ...) are skipped.

use std::fmt::Write as _;
use std::path::Path;

use super::cells::collect_tets;
use super::text::Cursor;
use super::{finish, integral_regions, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};

pub use super::cells::{VTK_QUADRATIC_TETRA, VTK_TETRA};

/// Loads a legacy VTK unstructured grid.
pub fn load_vtk_legacy(path: &Path) -> Result<(TetMesh, MeshReport)> {
    let bytes = read_file(path)?;
    let mut cur = Cursor::new(&bytes, path, None);
    let (_, magic) = cur.next_line().unwrap_or((1, ""));
    if !magic.to_ascii_lowercase().starts_with("# vtk datafile") {
        return Err(cur.err_at(
            1,
            "not a legacy VTK file: expected '# vtk DataFile Version x.x'",
        ));
    }
    cur.next_line(); // title
    let binary = match cur.token().map(str::to_ascii_uppercase).as_deref() {
        Some("ASCII") => false,
        Some("BINARY") => true,
        other => return Err(cur.err(format!("expected ASCII or BINARY, found {other:?}"))),
    };
    let dataset = (cur.token(), cur.token());
    if !matches!(dataset, (Some(d), Some(k)) if d.eq_ignore_ascii_case("DATASET")
        && k.eq_ignore_ascii_case("UNSTRUCTURED_GRID"))
    {
        return Err(cur.err(format!(
            "expected 'DATASET UNSTRUCTURED_GRID', found {:?} (only unstructured grids hold tets)",
            dataset
        )));
    }
    let mut r = Reader { cur, binary };
    let mut points: Option<Vec<f64>> = None;
    let mut cells: Option<CellList> = None;
    let mut types: Option<(Vec<f64>, usize)> = None;
    let mut section = Section::None;
    let mut scalars: Option<(String, Vec<f64>)> = None;
    let mut regions: Option<Vec<f64>> = None;
    let mut absorption: Option<Vec<f64>> = None;
    while let Some(word) = r.cur.token() {
        let line = r.cur.last_line();
        match word.to_ascii_uppercase().as_str() {
            "POINTS" => {
                let n: usize = r.cur.parse("the number of points")?;
                let ty = r.cur.expect("the point type")?;
                points = Some(r.values(ty, 3 * n, "point coordinates")?);
            }
            "CELLS" => cells = Some(r.cells()?),
            "CELL_TYPES" => {
                let n: usize = r.cur.parse("the number of cell types")?;
                types = Some((r.values("int", n, "cell types")?, line));
            }
            "POINT_DATA" | "CELL_DATA" => {
                let n: usize = r.cur.parse("the number of values")?;
                let point = word.eq_ignore_ascii_case("POINT_DATA");
                let want = if point {
                    points.as_ref().map_or(0, |p| p.len() / 3)
                } else {
                    cells.as_ref().map_or(0, |c| c.1.len() - 1)
                };
                if n != want {
                    return Err(r.cur.err(format!(
                        "{word} {n} does not match the {want} {}",
                        if point { "points" } else { "cells" }
                    )));
                }
                section = if point {
                    Section::Point(n)
                } else {
                    Section::Cell(n)
                };
            }
            "SCALARS" => {
                let name = r.cur.expect("the array name")?.to_string();
                let ty = r.cur.expect("the array type")?;
                let ncomp = match r.cur.peek() {
                    Some(t) if t.parse::<usize>().is_ok() => r.cur.parse("components")?,
                    _ => 1usize,
                };
                if r.cur
                    .peek()
                    .is_some_and(|t| t.eq_ignore_ascii_case("LOOKUP_TABLE"))
                {
                    r.cur.token();
                    r.cur.expect("the lookup table name")?;
                }
                let n = section
                    .count()
                    .ok_or_else(|| r.cur.err("SCALARS outside POINT_DATA/CELL_DATA"))?;
                let values = r.values(ty, n * ncomp, "scalar values")?;
                match (section, ncomp) {
                    (Section::Point(_), 1) if scalars.is_none() => scalars = Some((name, values)),
                    (Section::Cell(_), 3) if name.eq_ignore_ascii_case("absorption") => {
                        absorption = Some(values)
                    }
                    (Section::Cell(_), 1)
                        if regions.is_none() && integral_regions(&values).is_some() =>
                    {
                        regions = Some(values)
                    }
                    _ => {}
                }
            }
            "LOOKUP_TABLE" => {
                r.cur.expect("the table name")?;
                let n: usize = r.cur.parse("the table size")?;
                r.values(
                    if r.binary { "unsigned_char" } else { "float" },
                    4 * n,
                    "lookup table",
                )?;
            }
            "COLOR_SCALARS" => {
                r.cur.expect("the array name")?;
                let ncomp: usize = r.cur.parse("components")?;
                let n = section
                    .count()
                    .ok_or_else(|| r.cur.err("COLOR_SCALARS outside POINT_DATA/CELL_DATA"))?;
                r.values(
                    if r.binary { "unsigned_char" } else { "float" },
                    n * ncomp,
                    "colours",
                )?;
            }
            "VECTORS" | "NORMALS" | "TENSORS" => {
                r.cur.expect("the array name")?;
                let ty = r.cur.expect("the array type")?;
                let per = if word.eq_ignore_ascii_case("TENSORS") {
                    9
                } else {
                    3
                };
                let n = section
                    .count()
                    .ok_or_else(|| r.cur.err(format!("{word} outside POINT_DATA/CELL_DATA")))?;
                r.values(ty, n * per, "attribute values")?;
            }
            "TEXTURE_COORDINATES" => {
                r.cur.expect("the array name")?;
                let dim: usize = r.cur.parse("the dimension")?;
                let ty = r.cur.expect("the array type")?;
                let n = section.count().ok_or_else(|| {
                    r.cur
                        .err("TEXTURE_COORDINATES outside POINT_DATA/CELL_DATA")
                })?;
                r.values(ty, n * dim, "texture coordinates")?;
            }
            "FIELD" => {
                r.cur.expect("the field name")?;
                let arrays: usize = r.cur.parse("the number of arrays")?;
                for _ in 0..arrays {
                    r.cur.expect("the array name")?;
                    let ncomp: usize = r.cur.parse("components")?;
                    let ntuples: usize = r.cur.parse("tuples")?;
                    let ty = r.cur.expect("the array type")?;
                    r.values(ty, ncomp * ntuples, "field values")?;
                }
            }
            "METADATA" => {
                while let Some((_, text)) = r.cur.next_line() {
                    if text.trim().is_empty() && r.cur.last_line() > line + 1 {
                        break;
                    }
                }
            }
            _ => return Err(r.cur.err(format!("unexpected keyword {word:?}"))),
        }
    }
    let cur = &r.cur;
    let points = points.ok_or_else(|| DataError::format(path, "no POINTS section"))?;
    let (conn, starts, cell_lines) =
        cells.ok_or_else(|| DataError::format(path, "no CELLS section"))?;
    let (types, types_line) =
        types.ok_or_else(|| DataError::format(path, "no CELL_TYPES section"))?;
    if types.len() != starts.len() - 1 {
        return Err(cur.err_at(
            types_line,
            format!(
                "CELL_TYPES has {} entries but CELLS has {}",
                types.len(),
                starts.len() - 1
            ),
        ));
    }
    let npoints = points.len() / 3;
    let found = collect_tets(
        &conn,
        &starts,
        &types,
        npoints,
        |c, msg| match &cell_lines {
            Some(lines) => cur.err_at(lines[c], msg),
            None => DataError::format(path, format!("CELLS section: {msg}")),
        },
    )?;
    let mut mesh = TetMesh::new(
        points
            .chunks_exact(3)
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
            .collect(),
        found.tets,
    );
    if let Some((name, values)) = scalars {
        mesh.scalars = Some(values.iter().map(|&v| v as f32).collect());
        mesh.scalar_name = name;
    }
    if let Some(values) = regions.as_deref().and_then(integral_regions) {
        mesh.regions = Some(found.kept.iter().map(|&c| values[c]).collect());
    }
    if let Some(values) = absorption {
        mesh.absorption = Some(
            found
                .kept
                .iter()
                .map(|&c| {
                    [
                        values[3 * c] as f32,
                        values[3 * c + 1] as f32,
                        values[3 * c + 2] as f32,
                    ]
                })
                .collect(),
        );
    }
    finish(mesh, path, found.skipped)
}

/// Connectivity, cell starts and (ASCII classic layout) the line of every cell.
type CellList = (Vec<f64>, Vec<usize>, Option<Vec<usize>>);

#[derive(Clone, Copy)]
enum Section {
    None,
    Point(usize),
    Cell(usize),
}

impl Section {
    fn count(self) -> Option<usize> {
        match self {
            Section::None => None,
            Section::Point(n) | Section::Cell(n) => Some(n),
        }
    }
}

struct Reader<'a> {
    cur: Cursor<'a>,
    binary: bool,
}

impl Reader<'_> {
    /// `count` values of VTK type `ty`, as text or big-endian binary.
    fn values(&mut self, ty: &str, count: usize, what: &str) -> Result<Vec<f64>> {
        let lower = ty.to_ascii_lowercase();
        let size = match lower.as_str() {
            "bit" => return Err(self.cur.err("bit arrays are not supported")),
            "unsigned_char" | "char" | "vtktypeuint8" | "vtktypeint8" => 1,
            "short" | "unsigned_short" | "vtktypeint16" | "vtktypeuint16" => 2,
            "int" | "unsigned_int" | "float" | "vtktypeint32" | "vtktypeuint32" => 4,
            "long" | "unsigned_long" | "double" | "vtktypeint64" | "vtktypeuint64" => 8,
            _ => return Err(self.cur.err(format!("unknown data type {ty:?}"))),
        };
        if !self.binary {
            return (0..count).map(|_| self.cur.parse::<f64>(what)).collect();
        }
        self.cur.skip_line_end();
        let bytes = self.cur.bytes(
            count
                .checked_mul(size)
                .ok_or_else(|| self.cur.err("size overflow"))?,
            what,
        )?;
        let signed = !lower.contains("unsigned") && !lower.contains("uint");
        Ok(bytes
            .chunks_exact(size)
            .map(|b| match (size, lower.as_str()) {
                (4, "float") => f64::from(f32::from_be_bytes(b.try_into().expect("4 bytes"))),
                (8, "double") => f64::from_be_bytes(b.try_into().expect("8 bytes")),
                _ => {
                    let mut v: u64 = 0;
                    for &x in b {
                        v = v << 8 | u64::from(x);
                    }
                    let shift = 64 - 8 * size as u32;
                    if signed {
                        ((v << shift) as i64 >> shift) as f64
                    } else {
                        v as f64
                    }
                }
            })
            .collect())
    }

    /// A `CELLS` section: connectivity, cell starts and (for ASCII classic layout) the line
    /// of every cell.
    fn cells(&mut self) -> Result<CellList> {
        let n: usize = self.cur.parse("the number of cells")?;
        let size: usize = self.cur.parse("the cell list size")?;
        if self
            .cur
            .peek()
            .is_some_and(|t| t.eq_ignore_ascii_case("OFFSETS"))
        {
            self.cur.token();
            let ty = self.cur.expect("the offsets type")?;
            let offsets = self.values(ty, n, "cell offsets")?;
            let word = self.cur.expect("CONNECTIVITY")?;
            if !word.eq_ignore_ascii_case("CONNECTIVITY") {
                return Err(self
                    .cur
                    .err(format!("expected CONNECTIVITY, found {word:?}")));
            }
            let ty = self.cur.expect("the connectivity type")?;
            let conn = self.values(ty, size, "cell connectivity")?;
            let starts: Vec<usize> = offsets.iter().map(|&o| o as usize).collect();
            if starts.first() != Some(&0)
                || starts.windows(2).any(|w| w[0] > w[1])
                || starts.last() != Some(&size)
            {
                return Err(self
                    .cur
                    .err("OFFSETS must rise from 0 to the connectivity size"));
            }
            return Ok((conn, starts, None));
        }
        let mut lines = (!self.binary).then(|| Vec::with_capacity(n.min(1 << 24)));
        let list: Vec<f64> = if self.binary {
            self.values("int", size, "the cell list")?
        } else {
            let mut list = Vec::with_capacity(size.min(1 << 26));
            for c in 0..n {
                let k: usize = self.cur.parse("a cell's point count")?;
                lines.as_mut().expect("ascii").push(self.cur.last_line());
                list.push(k as f64);
                if list.len() + k > size {
                    return Err(self
                        .cur
                        .err(format!("cell {c} runs past the CELLS size {size}")));
                }
                for _ in 0..k {
                    list.push(self.cur.parse("a point index")?);
                }
            }
            if list.len() != size {
                return Err(self.cur.err(format!(
                    "CELLS size is {size} but the cells hold {} numbers",
                    list.len()
                )));
            }
            list
        };
        let mut conn = Vec::with_capacity(size.saturating_sub(n));
        let mut starts = vec![0];
        let mut at = 0;
        for c in 0..n {
            let k = *list
                .get(at)
                .ok_or_else(|| self.cur.err(format!("CELLS list ends inside cell {c}")))?
                as usize;
            let ids = list
                .get(at + 1..at + 1 + k)
                .ok_or_else(|| self.cur.err(format!("CELLS list ends inside cell {c}")))?;
            conn.extend_from_slice(ids);
            starts.push(conn.len());
            at += 1 + k;
        }
        Ok((conn, starts, lines))
    }
}

/// Writes an ASCII legacy VTK unstructured grid (version 3.0 layout) with the vertex
/// scalars as `POINT_DATA` and the regions and absorption as `CELL_DATA`.
pub fn write_vtk_legacy_ascii(mesh: &TetMesh, path: &Path) -> Result<()> {
    let mut s = String::new();
    let n = mesh.vertices.len();
    let _ = write!(s, "# vtk DataFile Version 3.0\ntessera tetrahedral mesh\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {n} float\n");
    for p in &mesh.vertices {
        let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
    }
    let m = mesh.tets.len();
    let _ = writeln!(s, "CELLS {m} {}", 5 * m);
    for t in &mesh.tets {
        let _ = writeln!(s, "4 {} {} {} {}", t[0], t[1], t[2], t[3]);
    }
    let _ = writeln!(s, "CELL_TYPES {m}");
    for _ in 0..m {
        s.push_str("10\n");
    }
    if mesh.regions.is_some() || mesh.absorption.is_some() {
        let _ = writeln!(s, "CELL_DATA {m}");
    }
    if let Some(r) = &mesh.regions {
        s.push_str("SCALARS region unsigned_int 1\nLOOKUP_TABLE default\n");
        r.iter().for_each(|v| {
            let _ = writeln!(s, "{v}");
        });
    }
    if let Some(a) = &mesh.absorption {
        s.push_str("SCALARS absorption float 3\nLOOKUP_TABLE default\n");
        a.iter().for_each(|v| {
            let _ = writeln!(s, "{} {} {}", v[0], v[1], v[2]);
        });
    }
    if let Some(values) = &mesh.scalars {
        let name = if mesh.scalar_name.is_empty() {
            "scalars".to_string()
        } else {
            mesh.scalar_name.replace(char::is_whitespace, "_")
        };
        let _ = writeln!(
            s,
            "POINT_DATA {n}\nSCALARS {name} float 1\nLOOKUP_TABLE default"
        );
        values.iter().for_each(|v| {
            let _ = writeln!(s, "{v}");
        });
    }
    write_file(path, s.as_bytes())
}

#[cfg(test)]
#[path = "vtk_legacy_tests.rs"]
mod tests;
