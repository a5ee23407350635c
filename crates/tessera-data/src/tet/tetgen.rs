//! TetGen `.node` / `.ele` pairs. Either file may be named; the other is the sibling with
//! the same stem. `#` starts a comment. Numbering starts at 0 or 1, as the first point of
//! the `.node` file says. The first point attribute becomes the vertex scalar
//! (`node_attribute_0`); a tet attribute becomes the region when every value is a
//! non-negative integer. Quadratic (10-node) tets keep their corner nodes.

use std::fmt::Write as _;
use std::path::Path;

use super::text::{field, Cursor};
use super::{finish, integral_regions, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};

/// Name given to the first point attribute of a `.node` file.
pub const NODE_SCALAR_NAME: &str = "node_attribute_0";

/// Loads `stem.node` + `stem.ele`; `path` may name either.
pub fn load_tetgen(path: &Path) -> Result<(TetMesh, MeshReport)> {
    let node_path = path.with_extension("node");
    let ele_path = path.with_extension("ele");
    let node_bytes = read_file(&node_path)?;
    let ele_bytes = read_file(&ele_path)?;
    parse_bytes(&node_bytes, &node_path, &ele_bytes, &ele_path)
}

/// Parses the bytes of a `.node` and an `.ele` file; the paths name them in errors.
pub fn parse_bytes(
    node_bytes: &[u8],
    node_path: &Path,
    ele_bytes: &[u8],
    ele_path: &Path,
) -> Result<(TetMesh, MeshReport)> {
    let (vertices, scalars, base) = parse_node(node_bytes, node_path)?;
    let (tets, attrs) = parse_ele(ele_bytes, ele_path, base, vertices.len())?;
    let mut mesh = TetMesh::new(vertices, tets);
    if let Some(values) = scalars {
        mesh.scalars = Some(values);
        mesh.scalar_name = NODE_SCALAR_NAME.into();
    }
    mesh.regions = attrs.as_deref().and_then(integral_regions);
    finish(mesh, ele_path, 0)
}

type NodeData = (Vec<[f32; 3]>, Option<Vec<f32>>, u64);

fn parse_node(bytes: &[u8], path: &Path) -> Result<NodeData> {
    let mut cur = Cursor::new(bytes, path, Some(b'#'));
    let (line, head) = cur
        .record()
        .ok_or_else(|| DataError::format(path, "empty .node file: no header line"))?;
    let count: usize = field(&cur, line, &head, 0, "the number of points")?;
    let dim: usize = field(&cur, line, &head, 1, "the dimension (3)")?;
    let nattr: usize = if head.len() > 2 {
        field(&cur, line, &head, 2, "the attribute count")?
    } else {
        0
    };
    let nmark: usize = if head.len() > 3 {
        field(&cur, line, &head, 3, "the marker count (0 or 1)")?
    } else {
        0
    };
    if dim != 3 {
        return Err(cur.err_at(
            line,
            format!("dimension {dim}: only 3D meshes are supported"),
        ));
    }
    let count = backed_by_file(&cur, line, count, "points")?;
    let width = nattr.saturating_add(nmark).saturating_add(4);
    let mut vertices = Vec::with_capacity(count);
    let mut scalars = (nattr > 0).then(|| Vec::with_capacity(count));
    let mut base = 0;
    for i in 0..count {
        let (line, f) = cur
            .record()
            .ok_or_else(|| cur.err(format!("file ends early: found {i} of {count} points")))?;
        if f.len() < width {
            return Err(cur.err_at(line, format!(
                "point line has {} fields, expected {} (index, x, y, z, {nattr} attribute(s), {nmark} marker(s))",
                f.len(), width
            )));
        }
        let index: u64 = field(&cur, line, &f, 0, "a point number")?;
        if i == 0 {
            if index > 1 {
                return Err(cur.err_at(
                    line,
                    format!("first point is numbered {index}, expected 0 or 1"),
                ));
            }
            base = index;
        } else if index != base + i as u64 {
            return Err(cur.err_at(
                line,
                format!(
                    "point number {index} out of sequence: expected {}",
                    base + i as u64
                ),
            ));
        }
        let mut p = [0f32; 3];
        for (c, value) in p.iter_mut().enumerate() {
            *value = field(&cur, line, &f, 1 + c, "a coordinate")?;
        }
        vertices.push(p);
        if let Some(s) = scalars.as_mut() {
            s.push(field(&cur, line, &f, 4, "a point attribute")?);
        }
    }
    Ok((vertices, scalars, base))
}

type EleData = (Vec<[u32; 4]>, Option<Vec<f64>>);

fn parse_ele(bytes: &[u8], path: &Path, base: u64, nverts: usize) -> Result<EleData> {
    let mut cur = Cursor::new(bytes, path, Some(b'#'));
    let (line, head) = cur
        .record()
        .ok_or_else(|| DataError::format(path, "empty .ele file: no header line"))?;
    let count: usize = field(&cur, line, &head, 0, "the number of tetrahedra")?;
    let per: usize = if head.len() > 1 {
        field(&cur, line, &head, 1, "nodes per tetrahedron")?
    } else {
        4
    };
    let nattr: usize = if head.len() > 2 {
        field(&cur, line, &head, 2, "the attribute count")?
    } else {
        0
    };
    if per != 4 && per != 10 {
        return Err(cur.err_at(
            line,
            format!("{per} nodes per tetrahedron: expected 4 or 10"),
        ));
    }
    let count = backed_by_file(&cur, line, count, "tetrahedra")?;
    let width = nattr.saturating_add(per).saturating_add(1);
    let mut tets = Vec::with_capacity(count);
    let mut attrs = (nattr > 0).then(|| Vec::with_capacity(count));
    for t in 0..count {
        let (line, f) = cur
            .record()
            .ok_or_else(|| cur.err(format!("file ends early: found {t} of {count} tetrahedra")))?;
        if f.len() < width {
            return Err(cur.err_at(
                line,
                format!(
                    "tetrahedron line has {} fields, expected {}",
                    f.len(),
                    width
                ),
            ));
        }
        let mut tet = [0u32; 4];
        for (k, slot) in tet.iter_mut().enumerate() {
            let raw: u64 = field(&cur, line, &f, 1 + k, "a point number")?;
            let index = raw.checked_sub(base).filter(|&i| i < nverts as u64);
            *slot = index.ok_or_else(|| {
                cur.err_at(
                    line,
                    format!(
                        "tet {t}: point number {raw} out of range \
                 (the .node file has {nverts} points numbered from {base})"
                    ),
                )
            })? as u32;
        }
        tets.push(tet);
        if let Some(a) = attrs.as_mut() {
            a.push(field(&cur, line, &f, 1 + per, "a tetrahedron attribute")?);
        }
    }
    Ok((tets, attrs))
}

/// A count from a header line, refused when the rest of the file has fewer lines than that
/// (each takes at least a byte), so that nothing is allocated for a count the file does not
/// back.
fn backed_by_file(cur: &Cursor, line: usize, count: usize, what: &str) -> Result<usize> {
    let left = cur.remaining();
    if count > left {
        return Err(cur.err_at(
            line,
            format!("{count} {what} announced, but only {left} bytes of the file remain"),
        ));
    }
    Ok(count)
}

/// Writes `stem.node` and `stem.ele` (numbered from 1) next to `path` (either extension).
/// The vertex scalars become a point attribute and the regions a tet attribute; absorption
/// colours have no place in the format and are not written.
pub fn write_tetgen(mesh: &TetMesh, path: &Path) -> Result<()> {
    let mut node = String::new();
    let nattr = usize::from(mesh.scalars.is_some());
    let _ = writeln!(
        node,
        "# written by tessera\n{} 3 {nattr} 0",
        mesh.vertices.len()
    );
    for (i, p) in mesh.vertices.iter().enumerate() {
        let _ = write!(node, "{} {} {} {}", i + 1, p[0], p[1], p[2]);
        if let Some(s) = &mesh.scalars {
            let _ = write!(node, " {}", s[i]);
        }
        node.push('\n');
    }
    write_file(&path.with_extension("node"), node.as_bytes())?;

    let mut ele = String::new();
    let nattr = usize::from(mesh.regions.is_some());
    let _ = writeln!(ele, "# written by tessera\n{} 4 {nattr}", mesh.tets.len());
    for (t, tet) in mesh.tets.iter().enumerate() {
        let _ = write!(
            ele,
            "{} {} {} {} {}",
            t + 1,
            tet[0] + 1,
            tet[1] + 1,
            tet[2] + 1,
            tet[3] + 1
        );
        if let Some(r) = &mesh.regions {
            let _ = write!(ele, " {}", r[t]);
        }
        ele.push('\n');
    }
    write_file(&path.with_extension("ele"), ele.as_bytes())
}

#[cfg(test)]
#[path = "tetgen_tests.rs"]
mod tests;
