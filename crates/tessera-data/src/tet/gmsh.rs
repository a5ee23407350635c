//! Gmsh `.msh` files, format 4.1 ASCII: `$Nodes` and `$Elements` with entity blocks.
//! Element type 4 (4-node tet) is kept and type 11 (10-node tet) keeps its corners; every
//! other element type is skipped and counted. The entity tag of each tet's block becomes its
//! region; the first one-component `$NodeData` becomes the vertex scalar (nodes it leaves
//! out get NaN). Other sections are skipped. Binary files and format 2 are refused with a
//! clear message.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use super::text::{field, Cursor};
use super::{finish, read_file, write_file, MeshReport, TetMesh};
use crate::error::{DataError, Result};

/// Gmsh element types that become tets.
pub const MSH_TET4: u32 = 4;
pub const MSH_TET10: u32 = 11;

/// Loads a Gmsh 4.1 ASCII mesh.
pub fn load_msh(path: &Path) -> Result<(TetMesh, MeshReport)> {
    let bytes = read_file(path)?;
    let mut cur = Cursor::new(&bytes, path, None);
    let mut format_seen = false;
    let mut vertices = Vec::new();
    let mut tag_index: HashMap<u64, u32> = HashMap::new();
    let mut tets = Vec::new();
    let mut regions = Vec::new();
    let mut skipped = 0;
    let mut scalars: Option<(String, Vec<f32>)> = None;
    while let Some((line, fields)) = cur.record() {
        let section = fields[0];
        if !section.starts_with('$') {
            return Err(cur.err_at(
                line,
                format!("expected a section such as $Nodes, found {section:?}"),
            ));
        }
        if !format_seen && section != "$MeshFormat" {
            return Err(cur.err_at(
                line,
                "not a Gmsh mesh: the file must start with $MeshFormat",
            ));
        }
        match section {
            "$MeshFormat" => {
                let (line, f) = cur
                    .record()
                    .ok_or_else(|| cur.err("file ends inside $MeshFormat"))?;
                let version = f[0];
                let file_type: u32 = field(&cur, line, &f, 1, "the file type (0 = ASCII)")?;
                if !version.starts_with("4.1") {
                    return Err(cur.err_at(line, format!(
                        "msh format {version} is not supported: save the mesh as version 4.1 (ASCII)"
                    )));
                }
                if file_type != 0 {
                    return Err(cur.err_at(
                        line,
                        "binary msh not supported yet: save the mesh as ASCII 4.1",
                    ));
                }
                format_seen = true;
            }
            "$Nodes" => read_nodes(&mut cur, &mut vertices, &mut tag_index)?,
            "$Elements" => {
                read_elements(&mut cur, &tag_index, &mut tets, &mut regions, &mut skipped)?
            }
            "$NodeData" if scalars.is_none() => scalars = read_node_data(&mut cur, &tag_index)?,
            _ => {}
        }
        if !format_seen {
            return Err(cur.err_at(
                line,
                "not a Gmsh mesh: the file must start with $MeshFormat",
            ));
        }
        let end = format!("$End{}", &section[1..]);
        loop {
            let (_, f) = cur
                .record()
                .ok_or_else(|| cur.err(format!("file ends before {end}")))?;
            if f[0] == end {
                break;
            }
        }
    }
    if !format_seen {
        return Err(DataError::format(
            path,
            "not a Gmsh mesh: no $MeshFormat section",
        ));
    }
    let mut mesh = TetMesh::new(vertices, tets);
    mesh.regions = Some(regions);
    if let Some((name, values)) = scalars {
        mesh.scalars = Some(values);
        mesh.scalar_name = name;
    }
    finish(mesh, path, skipped)
}

fn read_nodes(
    cur: &mut Cursor,
    vertices: &mut Vec<[f32; 3]>,
    tag_index: &mut HashMap<u64, u32>,
) -> Result<()> {
    let blocks: usize = cur.parse("the number of node blocks")?;
    let total: usize = cur.parse("the number of nodes")?;
    cur.parse::<u64>("the smallest node tag")?;
    cur.parse::<u64>("the largest node tag")?;
    vertices.reserve(total.min(1 << 24));
    for _ in 0..blocks {
        let dim: usize = cur.parse("the entity dimension")?;
        cur.parse::<i64>("the entity tag")?;
        let parametric: u32 = cur.parse("the parametric flag")?;
        let n: usize = cur.parse("the number of nodes in the block")?;
        let first = vertices.len();
        for k in 0..n {
            let tag: u64 = cur.parse("a node tag")?;
            if tag_index.insert(tag, (first + k) as u32).is_some() {
                return Err(cur.err(format!("node tag {tag} defined twice")));
            }
        }
        for _ in 0..n {
            let mut p = [0f32; 3];
            for c in &mut p {
                *c = cur.parse("a node coordinate")?;
            }
            for _ in 0..(if parametric != 0 { dim } else { 0 }) {
                cur.parse::<f64>("a parametric coordinate")?;
            }
            vertices.push(p);
        }
    }
    if vertices.len() != total {
        return Err(cur.err(format!(
            "$Nodes announces {total} nodes but its blocks hold {}",
            vertices.len()
        )));
    }
    Ok(())
}

fn read_elements(
    cur: &mut Cursor,
    tag_index: &HashMap<u64, u32>,
    tets: &mut Vec<[u32; 4]>,
    regions: &mut Vec<u32>,
    skipped: &mut usize,
) -> Result<()> {
    let blocks: usize = cur.parse("the number of element blocks")?;
    let total: usize = cur.parse("the number of elements")?;
    cur.parse::<u64>("the smallest element tag")?;
    cur.parse::<u64>("the largest element tag")?;
    let mut count = 0;
    for _ in 0..blocks {
        cur.parse::<u32>("the entity dimension")?;
        let entity: u32 = cur.parse("the entity tag")?;
        let kind: u32 = cur.parse("the element type")?;
        let n: usize = cur.parse("the number of elements in the block")?;
        for e in 0..n {
            let (line, f) = cur.record().ok_or_else(|| {
                cur.err(format!(
                    "file ends inside an element block (element {e} of {n})"
                ))
            })?;
            count += 1;
            if kind != MSH_TET4 && kind != MSH_TET10 {
                *skipped += 1;
                continue;
            }
            let want = if kind == MSH_TET4 { 4 } else { 10 };
            if f.len() != want + 1 {
                return Err(cur.err_at(
                    line,
                    format!(
                        "element of type {kind} has {} node tags, expected {want}",
                        f.len() - 1
                    ),
                ));
            }
            let element: u64 = field(cur, line, &f, 0, "an element tag")?;
            let mut tet = [0u32; 4];
            for (k, slot) in tet.iter_mut().enumerate() {
                let tag: u64 = field(cur, line, &f, 1 + k, "a node tag")?;
                *slot = *tag_index.get(&tag).ok_or_else(|| cur.err_at(line, format!(
                    "tet {} (element {element}): node tag {tag} out of range (not defined in $Nodes)", tets.len()
                )))?;
            }
            tets.push(tet);
            regions.push(entity);
        }
    }
    if count != total {
        return Err(cur.err(format!(
            "$Elements announces {total} elements but its blocks hold {count}"
        )));
    }
    Ok(())
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

fn read_node_data(cur: &mut Cursor, tag_index: &HashMap<u64, u32>) -> Result<NodeData> {
    let n_str = tag_count(cur, "the string tag count")?;
    let strings = tag_lines(cur, n_str, "string tags")?;
    let n_real = tag_count(cur, "the real tag count")?;
    tag_lines(cur, n_real, "real tags")?;
    let n_int = tag_count(cur, "the integer tag count")?;
    let ints = tag_lines(cur, n_int, "integer tags")?;
    let ncomp: usize = ints.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let entries: usize = ints.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
    let name = strings
        .first()
        .map_or("node_data".to_string(), |s| s.trim_matches('"').to_string());
    let mut values = vec![f32::NAN; tag_index.len()];
    for _ in 0..entries {
        let (line, f) = cur
            .record()
            .ok_or_else(|| cur.err("file ends inside $NodeData"))?;
        if ncomp != 1 {
            continue;
        }
        let tag: u64 = field(cur, line, &f, 0, "a node tag")?;
        let index = tag_index
            .get(&tag)
            .ok_or_else(|| cur.err_at(line, format!("$NodeData names unknown node tag {tag}")))?;
        values[*index as usize] = field(cur, line, &f, 1, "a value")?;
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
#[path = "gmsh_tests.rs"]
mod tests;
