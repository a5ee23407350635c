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
use super::{finish, integral_regions, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};
use crate::vtk_xml::{Need, VtkXml};

/// Loads a VTK XML unstructured grid.
pub fn load_vtu(path: &Path) -> Result<(TetMesh, MeshReport)> {
    parse_bytes(&read_file(path)?, path)
}

/// Parses the bytes of a VTK XML unstructured grid; `path` names the file in errors.
pub fn parse_bytes(data: &[u8], path: &Path) -> Result<(TetMesh, MeshReport)> {
    let file = VtkXml::open(
        data,
        path,
        "UnstructuredGrid",
        "a tetrahedral mesh (VTK XML unstructured grid)",
    )?;
    let grid = file
        .child(file.root(), "UnstructuredGrid")
        .ok_or_else(|| file.err(file.root(), "no <UnstructuredGrid> in the VTKFile"))?;
    let mut mesh = TetMesh::default();
    let (mut scalars, mut regions, mut absorption) =
        (Some(Vec::new()), Some(Vec::new()), Some(Vec::new()));
    let mut skipped = 0;
    let mut pieces = 0;
    for p in file.children(grid, "Piece") {
        pieces += 1;
        let piece = Piece::read(&file, p)?;
        let points = file
            .arrays(p, "Points")
            .into_iter()
            .next()
            .ok_or_else(|| file.err(p, "<Piece> without <Points>"))?;
        let coords = file.values(points, piece.points(3))?;
        let cells = file.arrays(p, "Cells");
        let named = |name: &str| {
            cells
                .iter()
                .copied()
                .find(|&e| file.element(e).attr("Name") == Some(name))
                .ok_or_else(|| file.err(p, format!("<Cells> has no {name} DataArray")))
        };
        let (conn_el, offsets_el, types_el) =
            (named("connectivity")?, named("offsets")?, named("types")?);
        let offsets = file.values(offsets_el, piece.cells(1))?;
        let types = file.values(types_el, piece.cells(1))?;
        let mut starts = vec![0];
        starts.extend(offsets.iter().map(|&o| o as usize));
        if offsets.iter().any(|&o| o.is_nan() || o < 0.0) || starts.windows(2).any(|w| w[0] > w[1])
        {
            return Err(file.array_err(offsets_el, "cell offsets must rise from 0"));
        }
        let conn_len = *starts.last().expect("starts with 0");
        let last_offset = format!("the last offset ({conn_len})");
        let conn = file.values(
            conn_el,
            Need {
                tuples: conn_len,
                components: 1,
                source: &last_offset,
            },
        )?;
        let found = collect_tets(&conn, &starts, &types, piece.npoints, |_, msg| {
            file.array_err(conn_el, msg)
        })?;
        skipped += found.skipped;
        let base = u32::try_from(mesh.vertices.len() + piece.npoints)
            .map(|end| end - piece.npoints as u32)
            .map_err(|_| file.err(p, "the pieces hold more than 2^32 points"))?;
        mesh.vertices.extend(
            coords
                .chunks_exact(3)
                .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32]),
        );
        mesh.tets
            .extend(found.tets.iter().map(|t| t.map(|v| v + base)));

        let point_data = match file.scalar_candidates(p, "PointData")?.first() {
            Some(&i) => Some((array_name(&file, i), file.values(i, piece.points(1))?)),
            None => None,
        };
        match (&mut scalars, point_data) {
            (Some(s), Some((name, values))) => {
                if mesh.scalar_name.is_empty() {
                    mesh.scalar_name = name;
                }
                s.extend(values.iter().map(|&v| v as f32));
            }
            _ => scalars = None,
        }
        let mut region_values = None;
        for i in file.scalar_candidates(p, "CellData")? {
            if array_name(&file, i) == "absorption" {
                continue;
            }
            let values = file.values(i, piece.cells(1))?;
            if integral_regions(&values).is_some() {
                region_values = Some(values);
                break;
            }
        }
        match (&mut regions, region_values) {
            (Some(r), Some(values)) => r.extend(found.kept.iter().map(|&c| values[c] as u32)),
            _ => regions = None,
        }
        let colours = match file
            .arrays(p, "CellData")
            .into_iter()
            .find(|&i| file.element(i).attr("Name") == Some("absorption"))
        {
            Some(i) => Some(file.values(i, piece.cells(3))?),
            None => None,
        };
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
    if pieces == 0 {
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

fn array_name(file: &VtkXml, index: usize) -> String {
    file.element(index)
        .attr("Name")
        .unwrap_or("scalars")
        .to_string()
}

/// The point and cell counts of a `<Piece>`, and the attribute text they come from.
struct Piece {
    npoints: usize,
    ncells: usize,
    points_source: String,
    cells_source: String,
}

impl Piece {
    fn read(file: &VtkXml, p: usize) -> Result<Piece> {
        let count = |name: &str| -> Result<(usize, String)> {
            let text = file.element(p).attr(name);
            text.and_then(|v| v.trim().parse().ok())
                .map(|n| (n, format!("{name}=\"{}\"", text.unwrap_or_default())))
                .ok_or_else(|| file.err(p, format!("<Piece> needs a numeric {name}")))
        };
        let (npoints, points_source) = count("NumberOfPoints")?;
        let (ncells, cells_source) = count("NumberOfCells")?;
        Ok(Piece {
            npoints,
            ncells,
            points_source,
            cells_source,
        })
    }

    fn points(&self, components: usize) -> Need<'_> {
        Need {
            tuples: self.npoints,
            components,
            source: &self.points_source,
        }
    }

    fn cells(&self, components: usize) -> Need<'_> {
        Need {
            tuples: self.ncells,
            components,
            source: &self.cells_source,
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
