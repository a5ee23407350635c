//! VTK XML unstructured grids (`.vtu`). `DataArray`s may be `ascii`, inline base64
//! `binary` or `appended` (raw or base64), with `UInt32`/`UInt64` block headers, optionally
//! zlib-compressed (`vtkZLibDataCompressor`), little- or big-endian. Several `Piece`s are
//! merged. Cell handling and the choice of scalars follow [`super::vtk_legacy`]: tets (10)
//! and quadratic tets (24) are kept, other cells skipped and counted; the `Scalars` (or
//! first one-component) point array is the vertex scalar; in cell data a three-component
//! `absorption` array is the absorption colour and the `Scalars` (or first one-component)
//! integral array the region.

use std::fmt::Write as _;
use std::path::Path;

use super::cells::collect_tets;
use super::vtu_data::{base64_decode, convert, needed_bytes, type_size, unpack, Layout};
use super::xml::{line_of, parse, Document, Element};
use super::{finish, integral_regions, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};

/// Loads a VTK XML unstructured grid.
pub fn load_vtu(path: &Path) -> Result<(TetMesh, MeshReport)> {
    let data = read_file(path)?;
    let at = |pos: usize, msg: String| {
        DataError::format(path, format!("line {}: {msg}", line_of(&data, pos)))
    };
    let doc = parse(&data).map_err(|(pos, msg)| at(pos, msg))?;
    let root = doc
        .elements
        .first()
        .filter(|e| e.name == "VTKFile")
        .ok_or_else(|| DataError::format(path, "not a VTK XML file: no <VTKFile> element"))?;
    if root.attr("type") != Some("UnstructuredGrid") {
        return Err(at(
            root.pos,
            format!(
                "VTKFile type {:?}: only UnstructuredGrid holds tets",
                root.attr("type").unwrap_or("")
            ),
        ));
    }
    let layout = Layout {
        big_endian: match root.attr("byte_order").unwrap_or("LittleEndian") {
            "LittleEndian" => false,
            "BigEndian" => true,
            other => return Err(at(root.pos, format!("unknown byte_order {other:?}"))),
        },
        header_size: match root.attr("header_type").unwrap_or("UInt32") {
            "UInt32" => 4,
            "UInt64" => 8,
            other => return Err(at(root.pos, format!("unsupported header_type {other:?}"))),
        },
        compressed: match root.attr("compressor") {
            None | Some("") => false,
            Some("vtkZLibDataCompressor") => true,
            Some(other) => {
                return Err(at(
                    root.pos,
                    format!("compressor {other:?} is not supported (only vtkZLibDataCompressor)"),
                ))
            }
        },
    };
    let reader = Reader {
        data: &data,
        doc: &doc,
        layout,
        path,
    };
    let mut mesh = TetMesh::default();
    let (mut scalars, mut regions, mut absorption) =
        (Some(Vec::new()), Some(Vec::new()), Some(Vec::new()));
    let mut skipped = 0;
    let pieces: Vec<usize> = (0..doc.elements.len())
        .filter(|&i| doc.elements[i].name == "Piece")
        .collect();
    for &p in &pieces {
        let piece = &doc.elements[p];
        let count = |name: &str| -> Result<usize> {
            piece
                .attr(name)
                .and_then(|v| v.trim().parse().ok())
                .ok_or_else(|| at(piece.pos, format!("<Piece> needs a numeric {name}")))
        };
        let (npoints, ncells) = (count("NumberOfPoints")?, count("NumberOfCells")?);
        let points = reader
            .child_arrays(p, "Points")
            .into_iter()
            .next()
            .ok_or_else(|| at(piece.pos, "<Piece> without <Points>".into()))?;
        let coords = reader.values(points, npoints, 3)?;
        let cells = reader.child_arrays(p, "Cells");
        let named = |name: &str| {
            cells
                .iter()
                .copied()
                .find(|&e| doc.elements[e].attr("Name") == Some(name))
                .ok_or_else(|| at(piece.pos, format!("<Cells> has no {name} DataArray")))
        };
        let (conn_el, offsets_el, types_el) =
            (named("connectivity")?, named("offsets")?, named("types")?);
        let offsets = reader.values(offsets_el, ncells, 1)?;
        let types = reader.values(types_el, ncells, 1)?;
        let conn_len = offsets.last().map_or(0, |&o| o as usize);
        let conn = reader.values(conn_el, conn_len, 1)?;
        let mut starts = vec![0];
        starts.extend(offsets.iter().map(|&o| o as usize));
        if starts.windows(2).any(|w| w[0] > w[1]) {
            return Err(at(
                doc.elements[offsets_el].pos,
                "cell offsets decrease".into(),
            ));
        }
        let conn_pos = doc.elements[conn_el].pos;
        let found = collect_tets(&conn, &starts, &types, npoints, |_, msg| {
            at(conn_pos, format!("connectivity: {msg}"))
        })?;
        skipped += found.skipped;
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(
            coords
                .chunks_exact(3)
                .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32]),
        );
        mesh.tets
            .extend(found.tets.iter().map(|t| t.map(|v| v + base)));

        let point_data = reader.pick(p, "PointData", 1, npoints, |_| true)?;
        match (&mut scalars, point_data) {
            (Some(s), Some((name, values))) => {
                if mesh.scalar_name.is_empty() {
                    mesh.scalar_name = name;
                }
                s.extend(values.iter().map(|&v| v as f32));
            }
            _ => scalars = None,
        }
        let region_values =
            reader.pick(p, "CellData", 1, ncells, |v| integral_regions(v).is_some())?;
        match (&mut regions, region_values) {
            (Some(r), Some((_, values))) => r.extend(found.kept.iter().map(|&c| values[c] as u32)),
            _ => regions = None,
        }
        let colours = reader.named(p, "CellData", "absorption", 3, ncells)?;
        match (&mut absorption, colours) {
            (Some(a), Some(v)) => a.extend(
                found
                    .kept
                    .iter()
                    .map(|&c| [v[3 * c] as f32, v[3 * c + 1] as f32, v[3 * c + 2] as f32]),
            ),
            _ => absorption = None,
        }
    }
    if pieces.is_empty() {
        return Err(DataError::format(
            path,
            "no <Piece> in the UnstructuredGrid",
        ));
    }
    mesh.scalars = scalars;
    mesh.regions = regions;
    mesh.absorption = absorption;
    finish(mesh, path, skipped)
}

struct Reader<'a> {
    data: &'a [u8],
    doc: &'a Document,
    layout: Layout,
    path: &'a Path,
}

impl Reader<'_> {
    fn err(&self, e: &Element, msg: impl std::fmt::Display) -> DataError {
        let name = e.attr("Name").unwrap_or("unnamed");
        DataError::format(
            self.path,
            format!(
                "line {}: DataArray {name:?}: {msg}",
                line_of(self.data, e.pos)
            ),
        )
    }

    /// DataArrays inside the `section` child of piece `p`.
    fn child_arrays(&self, p: usize, section: &str) -> Vec<usize> {
        let els = &self.doc.elements;
        (0..els.len())
            .filter(|&i| els[i].name == "DataArray")
            .filter(|&i| {
                els[i]
                    .parent
                    .is_some_and(|s| els[s].name == section && els[s].parent == Some(p))
            })
            .collect()
    }

    /// The values of a DataArray, checked to hold `count` tuples of `ncomp` components.
    fn values(&self, index: usize, count: usize, ncomp: usize) -> Result<Vec<f64>> {
        let e = &self.doc.elements[index];
        let ty = e.attr("type").unwrap_or("");
        type_size(ty).ok_or_else(|| self.err(e, format!("unsupported type {ty:?}")))?;
        let comps: usize = e
            .attr("NumberOfComponents")
            .map_or(Ok(1), |v| v.trim().parse())
            .map_err(|_| self.err(e, "bad NumberOfComponents"))?;
        if comps != ncomp {
            return Err(self.err(e, format!("has {comps} components, expected {ncomp}")));
        }
        let want = count * ncomp;
        let format = e.attr("format").unwrap_or("ascii");
        let values = match format {
            "ascii" => {
                let text = String::from_utf8_lossy(&self.data[e.text.0..e.text.1]);
                text.split_whitespace()
                    .take(want + 1)
                    .map(|t| {
                        t.parse::<f64>()
                            .map_err(|_| self.err(e, format!("bad number {t:?}")))
                    })
                    .collect::<Result<Vec<_>>>()?
            }
            "binary" => {
                let bytes = base64_decode(&self.data[e.text.0..e.text.1], usize::MAX)
                    .map_err(|m| self.err(e, m))?;
                self.decode(e, &bytes, ty)?
            }
            "appended" => {
                let (base, encoding) = self
                    .doc
                    .appended
                    .as_ref()
                    .ok_or_else(|| self.err(e, "format appended but no <AppendedData>"))?;
                let offset: usize = e
                    .attr("offset")
                    .and_then(|v| v.trim().parse().ok())
                    .ok_or_else(|| self.err(e, "appended array without a numeric offset"))?;
                let start = self.data.get(base + offset..).ok_or_else(|| {
                    self.err(e, format!("offset {offset} is past the end of the file"))
                })?;
                if encoding == "base64" {
                    let head = base64_decode(start, self.layout.header_size * 3 + 64)
                        .map_err(|m| self.err(e, m))?;
                    let mut need = needed_bytes(&head, self.layout).map_err(|m| self.err(e, m))?;
                    let mut bytes = base64_decode(start, need).map_err(|m| self.err(e, m))?;
                    if self.layout.compressed {
                        need = needed_bytes(&bytes, self.layout).map_err(|m| self.err(e, m))?;
                        bytes = base64_decode(start, need).map_err(|m| self.err(e, m))?;
                    }
                    self.decode(e, &bytes, ty)?
                } else {
                    self.decode(e, start, ty)?
                }
            }
            other => return Err(self.err(e, format!("unknown format {other:?}"))),
        };
        if values.len() != want {
            return Err(self.err(
                e,
                format!(
                    "holds {} values, expected {want} ({count} x {ncomp}){}",
                    values.len(),
                    if values.len() < want {
                        ": truncated"
                    } else {
                        ""
                    }
                ),
            ));
        }
        Ok(values)
    }

    fn decode(&self, e: &Element, bytes: &[u8], ty: &str) -> Result<Vec<f64>> {
        let raw = unpack(bytes, self.layout).map_err(|m| self.err(e, m))?;
        convert(&raw, ty, self.layout.big_endian).map_err(|m| self.err(e, m))
    }

    /// The `Scalars`-named (or else first suitable) `ncomp`-component array of a section.
    fn pick(
        &self,
        p: usize,
        section: &str,
        ncomp: usize,
        count: usize,
        ok: impl Fn(&[f64]) -> bool,
    ) -> Result<Option<(String, Vec<f64>)>> {
        let els = &self.doc.elements;
        let arrays = self.child_arrays(p, section);
        let active = arrays
            .first()
            .and_then(|&a| els[a].parent)
            .and_then(|s| els[s].attr("Scalars"));
        let comps =
            |i: usize| els[i].attr("NumberOfComponents").unwrap_or("1").trim() == ncomp.to_string();
        let mut order: Vec<usize> = arrays
            .iter()
            .copied()
            .filter(|&i| els[i].attr("Name") == active && active.is_some())
            .collect();
        order.extend(
            arrays
                .iter()
                .copied()
                .filter(|&i| comps(i) && els[i].attr("Name") != Some("absorption")),
        );
        for i in order {
            if !comps(i) {
                continue;
            }
            let values = self.values(i, count, ncomp)?;
            if ok(&values) {
                return Ok(Some((
                    els[i].attr("Name").unwrap_or("scalars").to_string(),
                    values,
                )));
            }
        }
        Ok(None)
    }

    fn named(
        &self,
        p: usize,
        section: &str,
        name: &str,
        ncomp: usize,
        count: usize,
    ) -> Result<Option<Vec<f64>>> {
        let els = &self.doc.elements;
        match self
            .child_arrays(p, section)
            .into_iter()
            .find(|&i| els[i].attr("Name") == Some(name))
        {
            Some(i) => self.values(i, count, ncomp).map(Some),
            None => Ok(None),
        }
    }
}

/// Writes an ASCII VTK XML unstructured grid with the vertex scalars as point data and the
/// regions (`region`) and absorption colours (`absorption`) as cell data.
pub fn write_vtu_ascii(mesh: &TetMesh, path: &Path) -> Result<()> {
    let mut s = String::new();
    let (n, m) = (mesh.vertices.len(), mesh.tets.len());
    let _ = write!(s, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{m}\">\n");
    let array = |s: &mut String,
                 ty: &str,
                 name: &str,
                 ncomp: usize,
                 values: &mut dyn Iterator<Item = String>| {
        let name = name
            .replace('&', "&amp;")
            .replace('"', "&quot;")
            .replace('<', "&lt;");
        let _ = writeln!(s, "<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{ncomp}\" format=\"ascii\">");
        for v in values {
            s.push_str(&v);
            s.push('\n');
        }
        s.push_str("</DataArray>\n");
    };
    if let Some(values) = &mesh.scalars {
        let name = if mesh.scalar_name.is_empty() {
            "scalars"
        } else {
            &mesh.scalar_name
        };
        let _ = writeln!(
            s,
            "<PointData Scalars=\"{}\">",
            name.replace('&', "&amp;")
                .replace('"', "&quot;")
                .replace('<', "&lt;")
        );
        array(
            &mut s,
            "Float32",
            name,
            1,
            &mut values.iter().map(|v| v.to_string()),
        );
        s.push_str("</PointData>\n");
    }
    if mesh.regions.is_some() || mesh.absorption.is_some() {
        s.push_str("<CellData>\n");
        if let Some(r) = &mesh.regions {
            array(
                &mut s,
                "UInt32",
                "region",
                1,
                &mut r.iter().map(|v| v.to_string()),
            );
        }
        if let Some(a) = &mesh.absorption {
            array(
                &mut s,
                "Float32",
                "absorption",
                3,
                &mut a.iter().map(|v| format!("{} {} {}", v[0], v[1], v[2])),
            );
        }
        s.push_str("</CellData>\n");
    }
    s.push_str("<Points>\n");
    array(
        &mut s,
        "Float32",
        "Points",
        3,
        &mut mesh
            .vertices
            .iter()
            .map(|p| format!("{} {} {}", p[0], p[1], p[2])),
    );
    s.push_str("</Points>\n<Cells>\n");
    array(
        &mut s,
        "Int64",
        "connectivity",
        1,
        &mut mesh
            .tets
            .iter()
            .map(|t| format!("{} {} {} {}", t[0], t[1], t[2], t[3])),
    );
    array(
        &mut s,
        "Int64",
        "offsets",
        1,
        &mut (1..=m).map(|i| (4 * i).to_string()),
    );
    array(
        &mut s,
        "UInt8",
        "types",
        1,
        &mut (0..m).map(|_| "10".to_string()),
    );
    s.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    write_file(path, s.as_bytes())
}

#[cfg(test)]
#[path = "vtu_tests.rs"]
mod tests;
