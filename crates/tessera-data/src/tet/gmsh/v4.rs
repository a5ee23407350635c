//! The `$Nodes` and `$Elements` sections of format 4.1: entity blocks, each with its
//! entity, and in `$Elements` its element type.

use super::numbers::Numbers;
use super::{binary_element_nodes, Builder};
use crate::error::Result;

pub(super) fn nodes(n: &mut Numbers, mesh: &mut Builder) -> Result<()> {
    let blocks = n.size("the number of node blocks")?;
    let blocks = n.count("the number of node blocks", 20, blocks)?;
    let total = n.size("the number of nodes")?;
    let total = n.count("the number of nodes", 32, total)?;
    n.size("the smallest node tag")?;
    n.size("the largest node tag")?;
    mesh.vertices.reserve(total);
    let first = mesh.vertices.len();
    for _ in 0..blocks {
        let dim = n.int("the entity dimension")?;
        n.int("the entity tag")?;
        let parametric = n.int("the parametric flag")? != 0;
        let count = n.size("the number of nodes in the block")?;
        let count = n.count("the number of nodes in the block", 32, count)?;
        let extra = match (parametric, dim) {
            (false, _) => 0,
            (true, 0..=3) => dim as usize,
            (true, _) => return Err(n.err(format!("entity dimension {dim} is not 0 to 3"))),
        };
        let mut tags = Vec::with_capacity(count);
        for _ in 0..count {
            tags.push(n.size("a node tag")?);
        }
        for tag in tags {
            let mut p = [0f64; 3];
            for c in &mut p {
                *c = n.double("a node coordinate")?;
            }
            for _ in 0..extra {
                n.double("a parametric coordinate")?;
            }
            mesh.node(tag, p).map_err(|m| n.err(m))?;
        }
    }
    let found = mesh.vertices.len() - first;
    if found != total {
        return Err(n.err(format!(
            "$Nodes announces {total} nodes but its blocks hold {found}"
        )));
    }
    Ok(())
}

pub(super) fn elements(n: &mut Numbers, mesh: &mut Builder) -> Result<()> {
    let blocks = n.size("the number of element blocks")?;
    let blocks = n.count("the number of element blocks", 20, blocks)?;
    let total = n.size("the number of elements")?;
    n.size("the smallest element tag")?;
    n.size("the largest element tag")?;
    let mut count = 0u64;
    for _ in 0..blocks {
        n.int("the entity dimension")?;
        let entity = n.small("the entity tag")?;
        let kind = n.small("the element type")?;
        let in_block = n.size("the number of elements in the block")?;
        let in_block = n.count("the number of elements in the block", 16, in_block)?;
        for e in 0..in_block {
            let tags = match n.binary {
                Some(_) => {
                    let per = binary_element_nodes(n, kind)?;
                    (0..=per)
                        .map(|_| n.size("an element's tags"))
                        .collect::<Result<Vec<_>>>()?
                }
                None => {
                    let (line, f) = n.cur.record().ok_or_else(|| {
                        n.cur.err(format!(
                            "file ends inside an element block (element {e} of {in_block})"
                        ))
                    })?;
                    f.iter()
                        .map(|t| {
                            t.parse::<u64>().map_err(|_| {
                                n.cur.err_at(line, format!("expected a tag, found {t:?}"))
                            })
                        })
                        .collect::<Result<Vec<_>>>()?
                }
            };
            count += 1;
            mesh.element(tags[0], kind, entity, &tags[1..])
                .map_err(|m| n.err(m))?;
        }
    }
    if count != total {
        return Err(n.err(format!(
            "$Elements announces {total} elements but its blocks hold {count}"
        )));
    }
    Ok(())
}
