//! gmsh 4.1, ASCII and binary: `$Entities` carry the physical tags, `$Nodes` and `$Elements`
//! come in entity blocks.

use super::binary::Bin;
use super::element_types::{type_name, GmshType};
use super::text::{capped, Lines};
use super::{sections, RawElement, RawMesh, RawNode};
use crate::MeshError;
use std::collections::HashMap;

/// Physical tags of each entity, by (dimension, entity tag).
type Entities = HashMap<(i64, i64), Vec<i64>>;

/// A block of elements on one entity: elements `first..first + count` of `RawMesh::elements`.
struct ElementBlock {
    dim: i64,
    entity: i64,
    first: usize,
    count: usize,
}

pub(crate) fn parse(lines: &mut Lines, binary: bool) -> Result<RawMesh, MeshError> {
    let mut raw = RawMesh::new();
    let mut entities = Entities::new();
    let mut blocks = Vec::new();
    let (mut nodes_seen, mut elements_seen, mut entities_seen) = (false, false, false);
    while let Some(l) = lines.next_nonblank()? {
        match sections::header(lines, l)? {
            "PhysicalNames" => sections::physical_names(lines, &mut raw)?,
            "Entities" => {
                sections::once(lines, "Entities", &mut entities_seen)?;
                if binary {
                    entities_binary(lines, &mut entities)?;
                } else {
                    entities_ascii(lines, &mut entities)?;
                }
                lines.expect_end("Entities")?;
            }
            "PartitionedEntities" => {
                return Err(
                    lines.err("partitioned meshes are not read; save the mesh without partitions")
                )
            }
            "Nodes" => {
                sections::once(lines, "Nodes", &mut nodes_seen)?;
                if binary {
                    nodes_binary(lines, &mut raw)?;
                } else {
                    nodes_ascii(lines, &mut raw)?;
                }
                lines.expect_end("Nodes")?;
            }
            "Elements" => {
                sections::once(lines, "Elements", &mut elements_seen)?;
                if binary {
                    elements_binary(lines, &mut raw, &mut blocks)?;
                } else {
                    elements_ascii(lines, &mut raw, &mut blocks)?;
                }
                lines.expect_end("Elements")?;
            }
            other => lines.skip_section(other)?,
        }
    }
    sections::require(lines, nodes_seen, elements_seen)?;
    let mut phys_index = HashMap::new();
    for b in &blocks {
        let tags = entities
            .get(&(b.dim, b.entity))
            .cloned()
            .unwrap_or_default();
        let phys = raw.intern_phys(&tags, &mut phys_index);
        for e in &mut raw.elements[b.first..b.first + b.count] {
            e.phys = phys;
        }
    }
    Ok(raw)
}

fn entities_ascii(lines: &mut Lines, entities: &mut Entities) -> Result<(), MeshError> {
    let mut f = lines.fields("Entities")?;
    let counts = [
        f.count("number of points")?,
        f.count("number of curves")?,
        f.count("number of surfaces")?,
        f.count("number of volumes")?,
    ];
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let mut f = lines.fields("Entities")?;
            let tag = f.i64("entity tag")?;
            let n_coords = if dim == 0 { 3 } else { 6 };
            for _ in 0..n_coords {
                f.f64("entity coordinate")?;
            }
            let n_phys = f.count("number of physical tags")?;
            let mut phys = Vec::with_capacity(n_phys.min(64));
            for _ in 0..n_phys {
                phys.push(f.i64("physical tag")?);
            }
            if !phys.is_empty() {
                entities.insert((dim as i64, tag), phys);
            }
        }
    }
    Ok(())
}

fn entities_binary(lines: &mut Lines, entities: &mut Entities) -> Result<(), MeshError> {
    let mut b = Bin::new(lines.bytes, lines.pos, lines.file, lines.line, "Entities");
    let mut counts = [0usize; 4];
    for c in &mut counts {
        *c = b.count("number of entities", 4)?;
    }
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = b.int("entity tag")? as i64;
            let n_coords = if dim == 0 { 3 } else { 6 };
            for _ in 0..n_coords {
                b.real("entity coordinate")?;
            }
            let n_phys = b.count("number of physical tags", 4)?;
            let mut phys = Vec::with_capacity(n_phys.min(64));
            for _ in 0..n_phys {
                phys.push(b.int("physical tag")? as i64);
            }
            if dim > 0 {
                let n_bound = b.count("number of bounding entities", 4)?;
                for _ in 0..n_bound {
                    b.int("bounding entity tag")?;
                }
            }
            if !phys.is_empty() {
                entities.insert((dim as i64, tag), phys);
            }
        }
    }
    lines.advance_to(b.pos);
    Ok(())
}

/// Extra parametric coordinates stored per node of a block on an entity of dimension `dim`.
fn n_parametric(parametric: i64, dim: i64) -> usize {
    if parametric != 0 {
        dim.clamp(0, 3) as usize
    } else {
        0
    }
}

fn nodes_ascii(lines: &mut Lines, raw: &mut RawMesh) -> Result<(), MeshError> {
    let mut f = lines.fields("Nodes")?;
    let header_line = f.line;
    let n_blocks = f.count("number of entity blocks")?;
    let n_nodes = f.count("number of nodes")?;
    let tags = (f.u64("minimum node tag")?, f.u64("maximum node tag")?);
    raw.nodes
        .reserve(capped(n_nodes, 8, lines.bytes.len() - lines.pos));
    let first_node = raw.nodes.len();
    for _ in 0..n_blocks {
        let mut f = lines.fields("Nodes")?;
        let dim = f.i64("entity dimension")?;
        let _entity = f.i64("entity tag")?;
        let parametric = f.i64("parametric flag")?;
        let n = f.count("number of nodes in block")?;
        let first = raw.nodes.len();
        for _ in 0..n {
            let mut f = lines.fields("Nodes")?;
            raw.nodes.push(RawNode {
                tag: f.u64("node tag")?,
                xyz: [0.0; 3],
                line: f.line,
            });
        }
        let extra = n_parametric(parametric, dim);
        for node in &mut raw.nodes[first..] {
            let mut f = lines.fields("Nodes")?;
            node.xyz = [f.f64("x")?, f.f64("y")?, f.f64("z")?];
            for _ in 0..extra {
                f.f64("parametric coordinate")?;
            }
        }
    }
    let found = raw.nodes[first_node..].iter().map(|n| n.tag);
    check_totals(
        lines.file,
        header_line,
        "Nodes",
        "node",
        (n_nodes, tags),
        found,
    )
}

/// The `$Nodes` / `$Elements` header's totals (count, minimum and maximum tag) against the
/// blocks: a mismatch means blocks were lost, added or garbled.
fn check_totals(
    file: &str,
    line: usize,
    section: &str,
    what: &str,
    (count, (min, max)): (usize, (u64, u64)),
    tags: impl Iterator<Item = u64>,
) -> Result<(), MeshError> {
    let (mut n, mut lo, mut hi) = (0usize, u64::MAX, 0u64);
    for t in tags {
        n += 1;
        lo = lo.min(t);
        hi = hi.max(t);
    }
    if n != count || (n > 0 && (lo, hi) != (min, max)) {
        let found = if n > 0 {
            format!("{n} {what}s with tags {lo}..={hi}")
        } else {
            format!("no {what}")
        };
        return Err(MeshError::parse(
            file,
            line,
            format!(
                "the ${section} header says {count} {what}s with tags {min}..={max}, its blocks \
                 hold {found} (blocks lost, added or garbled?)"
            ),
        ));
    }
    Ok(())
}

fn nodes_binary(lines: &mut Lines, raw: &mut RawMesh) -> Result<(), MeshError> {
    let line = lines.line;
    let mut b = Bin::new(lines.bytes, lines.pos, lines.file, line, "Nodes");
    let n_blocks = b.count("number of entity blocks", 20)?;
    let n_nodes = b.count("number of nodes", 32)?;
    let tags = (b.size("minimum node tag")?, b.size("maximum node tag")?);
    raw.nodes.reserve(n_nodes);
    let first_node = raw.nodes.len();
    for _ in 0..n_blocks {
        let dim = b.int("entity dimension")? as i64;
        b.int("entity tag")?;
        let parametric = b.int("parametric flag")? as i64;
        let extra = n_parametric(parametric, dim);
        let n = b.count("number of nodes in block", 32 + 8 * extra)?;
        let first = raw.nodes.len();
        for _ in 0..n {
            raw.nodes.push(RawNode {
                tag: b.size("node tag")?,
                xyz: [0.0; 3],
                line,
            });
        }
        for node in &mut raw.nodes[first..] {
            node.xyz = [b.real("x")?, b.real("y")?, b.real("z")?];
            for _ in 0..extra {
                b.real("parametric coordinate")?;
            }
        }
    }
    let found = raw.nodes[first_node..].iter().map(|n| n.tag);
    check_totals(lines.file, line, "Nodes", "node", (n_nodes, tags), found)?;
    lines.advance_to(b.pos);
    Ok(())
}

fn unsupported(file: &str, line: usize, tag: u64, ty: i64) -> MeshError {
    MeshError::UnsupportedElement {
        file: file.to_string(),
        line,
        element_tag: tag,
        gmsh_type: ty,
        type_name: type_name(ty),
    }
}

fn elements_ascii(
    lines: &mut Lines,
    raw: &mut RawMesh,
    blocks: &mut Vec<ElementBlock>,
) -> Result<(), MeshError> {
    let mut f = lines.fields("Elements")?;
    let header_line = f.line;
    let n_blocks = f.count("number of entity blocks")?;
    let n_elements = f.count("number of elements")?;
    let tags = (f.u64("minimum element tag")?, f.u64("maximum element tag")?);
    raw.elements
        .reserve(capped(n_elements, 4, lines.bytes.len() - lines.pos));
    let first_element = raw.elements.len();
    for _ in 0..n_blocks {
        let mut f = lines.fields("Elements")?;
        let dim = f.i64("entity dimension")?;
        let entity = f.i64("entity tag")?;
        let type_number = f.i64("element type")?;
        let n = f.count("number of elements in block")?;
        let ty = GmshType::from_number(type_number);
        let first = raw.elements.len();
        for _ in 0..n {
            let mut f = lines.fields("Elements")?;
            let line = f.line;
            let tag = f.u64("element tag")?;
            let ty = ty.ok_or_else(|| unsupported(lines.file, line, tag, type_number))?;
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
            raw.elements.push(RawElement {
                tag,
                ty,
                start,
                phys: 0,
                line,
            });
        }
        blocks.push(ElementBlock {
            dim,
            entity,
            first,
            count: n,
        });
    }
    let found = raw.elements[first_element..].iter().map(|e| e.tag);
    check_totals(
        lines.file,
        header_line,
        "Elements",
        "element",
        (n_elements, tags),
        found,
    )
}

fn elements_binary(
    lines: &mut Lines,
    raw: &mut RawMesh,
    blocks: &mut Vec<ElementBlock>,
) -> Result<(), MeshError> {
    let line = lines.line;
    let mut b = Bin::new(lines.bytes, lines.pos, lines.file, line, "Elements");
    let n_blocks = b.count("number of entity blocks", 20)?;
    let n_elements = b.count("number of elements", 16)?;
    let tags = (
        b.size("minimum element tag")?,
        b.size("maximum element tag")?,
    );
    raw.elements.reserve(n_elements);
    let first_element = raw.elements.len();
    for _ in 0..n_blocks {
        let dim = b.int("entity dimension")? as i64;
        let entity = b.int("entity tag")? as i64;
        let type_number = b.int("element type")? as i64;
        let Some(ty) = GmshType::from_number(type_number) else {
            let n = b.size("number of elements in block")?;
            let tag = if n > 0 { b.size("element tag")? } else { 0 };
            return Err(unsupported(lines.file, line, tag, type_number));
        };
        let n = b.count("number of elements in block", 8 * (1 + ty.n_nodes()))?;
        let first = raw.elements.len();
        for _ in 0..n {
            let tag = b.size("element tag")?;
            let start = raw.conn.len();
            for _ in 0..ty.n_nodes() {
                raw.conn.push(b.size("node tag")?);
            }
            raw.elements.push(RawElement {
                tag,
                ty,
                start,
                phys: 0,
                line,
            });
        }
        blocks.push(ElementBlock {
            dim,
            entity,
            first,
            count: n,
        });
    }
    let found = raw.elements[first_element..].iter().map(|e| e.tag);
    check_totals(
        lines.file,
        line,
        "Elements",
        "element",
        (n_elements, tags),
        found,
    )?;
    lines.advance_to(b.pos);
    Ok(())
}
