//! The `$Nodes` and `$Elements` sections of format 2.2: a count line, then one node or
//! element per line (ASCII) or binary records, elements in runs of one type.

use super::numbers::Numbers;
use super::{binary_element_nodes, Builder};
use crate::error::Result;

pub(super) fn nodes(n: &mut Numbers, mesh: &mut Builder) -> Result<()> {
    let total = n.cur.parse::<u64>("the number of nodes")?;
    let total = n.count("the number of nodes", 28, total)?;
    if n.binary.is_some() {
        n.cur.skip_line_end();
    }
    mesh.vertices.reserve(total);
    for _ in 0..total {
        let tag = n.int("a node number")?;
        let tag =
            u64::try_from(tag).map_err(|_| n.err(format!("node number {tag} is negative")))?;
        let mut p = [0f64; 3];
        for c in &mut p {
            *c = n.double("a node coordinate")?;
        }
        mesh.node(tag, p).map_err(|m| n.err(m))?;
    }
    Ok(())
}

pub(super) fn elements(n: &mut Numbers, mesh: &mut Builder) -> Result<()> {
    let total = n.cur.parse::<u64>("the number of elements")?;
    let total = n.count("the number of elements", 12, total)?;
    if n.binary.is_none() {
        for _ in 0..total {
            let (line, f) = n
                .cur
                .record()
                .ok_or_else(|| n.cur.err("file ends inside $Elements"))?;
            let number = |i: usize| {
                f.get(i).and_then(|t| t.parse::<u64>().ok()).ok_or_else(|| {
                    n.cur.err_at(
                        line,
                        format!("expected 'number type tag-count tags... nodes...', found {f:?}"),
                    )
                })
            };
            let (element, kind, ntags) = (number(0)?, number(1)?, number(2)?);
            let first_node = usize::try_from(ntags)
                .ok()
                .and_then(|t| t.checked_add(3))
                .filter(|&at| at <= f.len())
                .ok_or_else(|| {
                    n.cur
                        .err_at(line, format!("{ntags} tags announced, the line has fewer"))
                })?;
            let tags = (3..first_node).map(number).collect::<Result<Vec<_>>>()?;
            let nodes = (first_node..f.len())
                .map(number)
                .collect::<Result<Vec<_>>>()?;
            let kind = u32::try_from(kind).unwrap_or(u32::MAX);
            mesh.element(element, kind, region(&tags), &nodes)
                .map_err(|m| n.cur.err_at(line, m))?;
        }
        return Ok(());
    }
    n.cur.skip_line_end();
    let mut read = 0;
    while read < total {
        let kind = n.small("an element type")?;
        let following = n.int("the number of elements that follow")?;
        let ntags = n.int("the number of tags")?;
        let per = binary_element_nodes(n, kind)?;
        let (Ok(following), Ok(ntags)) = (usize::try_from(following), usize::try_from(ntags))
        else {
            return Err(n.err("negative element or tag count"));
        };
        if following == 0 || following > total - read {
            return Err(n.err(format!(
                "{following} elements follow, but $Elements has {} left",
                total - read
            )));
        }
        n.count("the number of tags", 4, ntags as u64)?;
        for _ in 0..following {
            let element = n.int("an element number")?;
            let tags = (0..ntags)
                .map(|_| n.int("an element tag"))
                .collect::<Result<Vec<_>>>()?;
            let nodes = (0..per)
                .map(|_| n.int("a node number"))
                .collect::<Result<Vec<_>>>()?;
            let as_tags = |v: &[i64]| {
                v.iter()
                    .map(|&t| u64::try_from(t).unwrap_or(u64::MAX))
                    .collect::<Vec<_>>()
            };
            mesh.element(
                element as u64,
                kind,
                region(&as_tags(&tags)),
                &as_tags(&nodes),
            )
            .map_err(|m| n.err(m))?;
        }
        read += following;
    }
    Ok(())
}

/// The elementary entity of an element: its second tag, or its first when it has one only.
fn region(tags: &[u64]) -> u32 {
    let tag = tags.get(1).or(tags.first()).copied().unwrap_or(0);
    u32::try_from(tag).unwrap_or(u32::MAX)
}
