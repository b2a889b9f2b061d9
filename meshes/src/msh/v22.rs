//! gmsh 2.2 ASCII: `$Nodes` as `tag x y z`, `$Elements` as
//! `tag type n_tags physical elementary [...] node...`.

use super::element_types::{type_name, GmshType};
use super::text::{capped, Lines};
use super::{sections, RawElement, RawMesh, RawNode};
use crate::MeshError;
use std::collections::HashMap;

pub(crate) fn parse(lines: &mut Lines) -> Result<RawMesh, MeshError> {
    let mut raw = RawMesh::new();
    let mut phys_index = HashMap::new();
    let (mut nodes_seen, mut elements_seen) = (false, false);
    while let Some(l) = lines.next_nonblank()? {
        match sections::header(lines, l)? {
            "PhysicalNames" => sections::physical_names(lines, &mut raw)?,
            "Nodes" => {
                sections::once(lines, "Nodes", &mut nodes_seen)?;
                nodes(lines, &mut raw)?;
            }
            "Elements" => {
                sections::once(lines, "Elements", &mut elements_seen)?;
                elements(lines, &mut raw, &mut phys_index)?;
            }
            other => lines.skip_section(other)?,
        }
    }
    sections::require(lines, nodes_seen, elements_seen)?;
    Ok(raw)
}

fn nodes(lines: &mut Lines, raw: &mut RawMesh) -> Result<(), MeshError> {
    let n = lines.fields("Nodes")?.count("number of nodes")?;
    raw.nodes
        .reserve(capped(n, 8, lines.bytes.len() - lines.pos));
    for _ in 0..n {
        let mut f = lines.fields("Nodes")?;
        let tag = f.u64("node tag")?;
        let xyz = [f.f64("x")?, f.f64("y")?, f.f64("z")?];
        raw.nodes.push(RawNode {
            tag,
            xyz,
            line: f.line,
        });
    }
    lines.expect_end("Nodes")
}

fn elements(
    lines: &mut Lines,
    raw: &mut RawMesh,
    phys_index: &mut HashMap<Vec<i64>, usize>,
) -> Result<(), MeshError> {
    let n = lines.fields("Elements")?.count("number of elements")?;
    raw.elements
        .reserve(capped(n, 10, lines.bytes.len() - lines.pos));
    for _ in 0..n {
        let mut f = lines.fields("Elements")?;
        let line = f.line;
        let tag = f.u64("element tag")?;
        let type_number = f.i64("element type")?;
        let ty =
            GmshType::from_number(type_number).ok_or_else(|| MeshError::UnsupportedElement {
                file: lines.file.to_string(),
                line,
                element_tag: tag,
                gmsh_type: type_number,
                type_name: type_name(type_number),
            })?;
        let n_tags = f.count("number of tags")?;
        let mut physical = 0;
        for i in 0..n_tags {
            let t = f.i64("element tag list entry")?;
            if i == 0 {
                physical = t;
            }
        }
        let start = raw.conn.len();
        for _ in 0..ty.n_nodes() {
            raw.conn.push(f.u64("node tag")?);
        }
        let extra = f.rest().count();
        if extra > 0 {
            return Err(MeshError::parse(
                lines.file,
                line,
                format!(
                    "element {tag} of type {type_number} has {extra} fields more than its {} nodes",
                    ty.n_nodes()
                ),
            ));
        }
        let phys = if physical != 0 {
            raw.intern_phys(&[physical], phys_index)
        } else {
            0
        };
        raw.elements.push(RawElement {
            tag,
            ty,
            start,
            phys,
            line,
        });
    }
    lines.expect_end("Elements")
}
