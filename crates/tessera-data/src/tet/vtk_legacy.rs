//! Legacy VTK files (`.vtk`), `DATASET UNSTRUCTURED_GRID`, ASCII or BINARY (big-endian),
//! with the classic `CELLS n size` layout or the 5.1 `OFFSETS`/`CONNECTIVITY` one.
//!
//! Tetrahedra (cell type 10) are kept, quadratic tetrahedra (24) keep their corners, every
//! other cell type is skipped and counted. Attributes come from `SCALARS` or from the arrays
//! of a `FIELD` (as meshio writes them) alike: the first one-component array of `POINT_DATA`
//! becomes the vertex scalar; in `CELL_DATA` a three-component array named `absorption`
//! becomes the absorption colour and the first integral one-component array the region.
//! Other attributes (`VECTORS`, ...) are skipped.
//!
//! Counts in the file are checked against the bytes left before anything is allocated, and
//! each geometry section may appear once, before the attributes that refer to it.

use std::fmt::Write as _;
use std::path::Path;

use super::cells::collect_tets;
use super::text::{quoted, Cursor};
use super::{finish, integral_regions, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};

pub use super::cells::{VTK_QUADRATIC_TETRA, VTK_TETRA};

/// Loads a legacy VTK unstructured grid.
pub fn load_vtk_legacy(path: &Path) -> Result<(TetMesh, MeshReport)> {
    parse_bytes(&read_file(path)?, path)
}

/// Parses the bytes of a legacy VTK unstructured grid; `path` names the file in errors.
pub fn parse_bytes(bytes: &[u8], path: &Path) -> Result<(TetMesh, MeshReport)> {
    let mut cur = Cursor::new(bytes, path, None);
    let (_, magic) = cur.next_line().unwrap_or((1, ""));
    if !magic.to_ascii_lowercase().starts_with("# vtk datafile") {
        return Err(cur.err_at(
            1,
            "not a legacy VTK file: expected '# vtk DataFile Version x.x' \
             (the file was read as a legacy VTK mesh)",
        ));
    }
    cur.next_line(); // title
    let encoding = cur.token();
    let binary = match encoding.map(str::to_ascii_uppercase).as_deref() {
        Some("ASCII") => false,
        Some("BINARY") => true,
        _ => {
            return Err(cur.err(format!(
                "expected ASCII or BINARY on the third line of a legacy VTK file, found {}",
                quoted(encoding)
            )))
        }
    };
    let keyword = cur.token();
    let kind = cur.token();
    if !matches!((keyword, kind), (Some(d), Some(k)) if d.eq_ignore_ascii_case("DATASET")
        && k.eq_ignore_ascii_case("UNSTRUCTURED_GRID"))
    {
        let found = match (keyword, kind) {
            (Some(d), k) if d.eq_ignore_ascii_case("DATASET") => format!("DATASET {}", quoted(k)),
            (k, _) => quoted(k),
        };
        return Err(cur.err(format!(
            "expected 'DATASET UNSTRUCTURED_GRID', found {found}: the file was read as a \
             tetrahedral mesh, and only unstructured grids hold tetrahedra"
        )));
    }
    let mut r = Reader { cur, binary };
    let mut points: Option<(Vec<f64>, usize)> = None;
    let mut cells: Option<(CellList, usize)> = None;
    let mut types: Option<(Vec<f64>, usize)> = None;
    let mut section = Section::None;
    let mut kept = Attributes::default();
    while let Some(word) = r.cur.token() {
        let line = r.cur.last_line();
        let upper = word.to_ascii_uppercase();
        let once = |seen: Option<usize>| match seen {
            Some(first) => Err(r.cur.err(format!(
                "a second {upper} section (the first is on line {first}): \
                 a file holds one unstructured grid"
            ))),
            None => Ok(()),
        };
        match upper.as_str() {
            "POINTS" => {
                once(points.as_ref().map(|p| p.1))?;
                let n: usize = r.cur.parse("the number of points")?;
                let ty = r.cur.expect("the point type")?;
                let count = r.count(n, 3, "point coordinates")?;
                points = Some((r.values(ty, count, "point coordinates")?, line));
            }
            "CELLS" => {
                once(cells.as_ref().map(|c| c.1))?;
                cells = Some((r.cells()?, line));
            }
            "CELL_TYPES" => {
                once(types.as_ref().map(|t| t.1))?;
                let n: usize = r.cur.parse("the number of cell types")?;
                types = Some((r.values("int", n, "cell types")?, line));
            }
            "POINT_DATA" | "CELL_DATA" => {
                let n: usize = r.cur.parse("the number of values")?;
                let point = upper == "POINT_DATA";
                let (geometry, want) = if point {
                    ("POINTS", points.as_ref().map(|p| p.0.len() / 3))
                } else {
                    ("CELLS", cells.as_ref().map(|c| c.0 .1.len() - 1))
                };
                let want = want.ok_or_else(|| {
                    r.cur.err(format!(
                        "{upper} comes before {geometry}: attributes must follow the \
                         geometry they describe"
                    ))
                })?;
                if n != want {
                    return Err(r.cur.err(format!(
                        "{upper} {n} does not match the {want} {} of the {geometry} section",
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
                let n = r.section_count(section, &upper)?;
                let count = r.count(n, ncomp, "scalar values")?;
                let values = r.values(ty, count, "scalar values")?;
                kept.offer(section, name, ncomp, values);
            }
            "LOOKUP_TABLE" => {
                r.cur.expect("the table name")?;
                let n: usize = r.cur.parse("the table size")?;
                let count = r.count(n, 4, "lookup table")?;
                r.values(
                    if r.binary { "unsigned_char" } else { "float" },
                    count,
                    "lookup table",
                )?;
            }
            "COLOR_SCALARS" => {
                r.cur.expect("the array name")?;
                let ncomp: usize = r.cur.parse("components")?;
                let n = r.section_count(section, &upper)?;
                let count = r.count(n, ncomp, "colours")?;
                r.values(
                    if r.binary { "unsigned_char" } else { "float" },
                    count,
                    "colours",
                )?;
            }
            "VECTORS" | "NORMALS" | "TENSORS" => {
                r.cur.expect("the array name")?;
                let ty = r.cur.expect("the array type")?;
                let per = if upper == "TENSORS" { 9 } else { 3 };
                let n = r.section_count(section, &upper)?;
                let count = r.count(n, per, "attribute values")?;
                r.values(ty, count, "attribute values")?;
            }
            "TEXTURE_COORDINATES" => {
                r.cur.expect("the array name")?;
                let dim: usize = r.cur.parse("the dimension")?;
                let ty = r.cur.expect("the array type")?;
                let n = r.section_count(section, &upper)?;
                let count = r.count(n, dim, "texture coordinates")?;
                r.values(ty, count, "texture coordinates")?;
            }
            "FIELD" => {
                r.cur.expect("the field name")?;
                let arrays: usize = r.cur.parse("the number of arrays")?;
                for _ in 0..arrays {
                    let name = r.cur.expect("the array name")?.to_string();
                    // VTK writes an array it could not save as this one word.
                    if name == "NULL_ARRAY" {
                        continue;
                    }
                    let ncomp: usize = r.cur.parse("components")?;
                    let ntuples: usize = r.cur.parse("tuples")?;
                    let ty = r.cur.expect("the array type")?;
                    let count = r.count(ntuples, ncomp, "field values")?;
                    let values = r.values(ty, count, "field values")?;
                    // Field arrays may hold anything (a time value, say); only those with
                    // one tuple per point or cell of their section are attributes.
                    if section.count() == Some(ntuples) {
                        kept.offer(section, name, ncomp, values);
                    }
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
    let (points, _) = points.ok_or_else(|| DataError::format(path, "no POINTS section"))?;
    let ((conn, starts, cell_lines), _) =
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
    if let Some((name, values)) = kept.scalars {
        mesh.scalars = Some(values.iter().map(|&v| v as f32).collect());
        mesh.scalar_name = name;
    }
    if let Some(values) = kept.regions.as_deref().and_then(integral_regions) {
        mesh.regions = Some(found.kept.iter().map(|&c| values[c]).collect());
    }
    if let Some(values) = kept.absorption {
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

/// The point and cell arrays a mesh keeps, from `SCALARS` or `FIELD` arrays alike: the
/// first one-component point array, a three-component cell array named `absorption`, and
/// the first integral one-component cell array.
#[derive(Default)]
struct Attributes {
    scalars: Option<(String, Vec<f64>)>,
    regions: Option<Vec<f64>>,
    absorption: Option<Vec<f64>>,
}

impl Attributes {
    /// Keeps `values` (`ncomp` per tuple, one tuple per point or cell of `section`) if the
    /// mesh has a use for them.
    fn offer(&mut self, section: Section, name: String, ncomp: usize, values: Vec<f64>) {
        match (section, ncomp) {
            (Section::Point(_), 1) if self.scalars.is_none() => self.scalars = Some((name, values)),
            (Section::Cell(_), 3) if name.eq_ignore_ascii_case("absorption") => {
                self.absorption = Some(values)
            }
            (Section::Cell(_), 1)
                if self.regions.is_none() && integral_regions(&values).is_some() =>
            {
                self.regions = Some(values)
            }
            _ => {}
        }
    }
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
    /// The number of points or cells of the current `POINT_DATA`/`CELL_DATA` section.
    fn section_count(&self, section: Section, keyword: &str) -> Result<usize> {
        section.count().ok_or_else(|| {
            self.cur
                .err(format!("{keyword} outside POINT_DATA/CELL_DATA"))
        })
    }

    /// `tuples × components`, refused when the product overflows.
    fn count(&self, tuples: usize, components: usize, what: &str) -> Result<usize> {
        tuples.checked_mul(components).ok_or_else(|| {
            self.cur.err(format!(
                "{what}: {tuples} x {components} values is too many"
            ))
        })
    }

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
        // Every value takes at least one byte, so a count beyond the rest of the file is
        // refused before anything is allocated for it.
        let left = self.cur.remaining();
        if count > left {
            return Err(self.cur.err(format!(
                "{what}: {count} values announced, but only {left} bytes of the file remain"
            )));
        }
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
        let left = self.cur.remaining();
        if n > left || size > left {
            return Err(self.cur.err(format!(
                "CELLS {n} {size} announces more numbers than the {left} bytes left in the file"
            )));
        }
        let mut lines = (!self.binary).then(|| Vec::with_capacity(n));
        let list: Vec<f64> = if self.binary {
            self.values("int", size, "the cell list")?
        } else {
            let mut list = Vec::with_capacity(size);
            for c in 0..n {
                let k: usize = self.cur.parse("a cell's point count")?;
                lines.as_mut().expect("ascii").push(self.cur.last_line());
                // The cell takes 1 + k numbers of what is left of `size`.
                if k >= size - list.len() {
                    return Err(self
                        .cur
                        .err(format!("cell {c} runs past the CELLS size {size}")));
                }
                list.push(k as f64);
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
            let ids = at
                .checked_add(1 + k.min(size))
                .and_then(|end| list.get(at + 1..end))
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
