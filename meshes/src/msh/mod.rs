//! Reading gmsh `.msh` files: 2.2 ASCII, 4.1 ASCII and 4.1 binary (little-endian, data-size 8).
//!
//! What is kept:
//! - volume cells (hex8 = gmsh type 5, hex20 = 17) → one [`CellBlock`](crate::CellBlock) per
//!   physical volume name (and kind); cells in no physical volume → a block named `None`;
//! - quad4 (3) / quad8 (16) cells of a physical surface → `faces[name]`;
//! - `node_sets[name]`: the nodes of every element (points and lines too) of each physical group;
//! - nodes that no volume cell uses are dropped and the rest renumbered 0..n in file order
//!   (`node_tags` keeps the file's tags).
//!
//! Points (15) and lines (1, 8) only feed node sets; every other type is an error that names
//! the type, the element tag, the file and the line. An unnamed physical group is called
//! `physical_<tag>`. A volume cell in several physical volumes goes to the first one's block.
//! Hexahedra with negative orientation at the centroid are flipped (bottom ↔ top face), so
//! every cell has a positive Jacobian in squeal's (VTK's) node order; hex20 nodes are permuted
//! from gmsh's order (see `element_types::HEX20_FROM_GMSH`). A cell whose Jacobian is then not
//! positive at every corner (hex8) or every node (hex20) is an error naming the element and the
//! node ([`crate::jacobian`]). In 4.1 files the `$Nodes` and `$Elements` header totals (count,
//! smallest and largest tag) must match the blocks.

mod binary;
mod build;
mod element_types;
mod sections;
mod text;
mod v22;
mod v41;

use crate::{Mesh, MeshError};
use std::collections::HashMap;
use std::path::Path;
use text::Lines;

/// Reads a gmsh `.msh` file (2.2 ASCII, 4.1 ASCII or 4.1 binary).
pub fn read_msh(path: &Path) -> Result<Mesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_msh(&bytes, &path.display().to_string())
}

/// Parses the contents of a `.msh` file; `file_name` is used in error messages only.
pub fn parse_msh(bytes: &[u8], file_name: &str) -> Result<Mesh, MeshError> {
    let mut lines = Lines::new(bytes, file_name);
    let format = read_format(&mut lines)?;
    let raw = match format {
        Format::V22 => v22::parse(&mut lines)?,
        Format::V41 { binary } => v41::parse(&mut lines, binary)?,
    };
    build::build(raw, file_name)
}

/// One node as read.
pub(crate) struct RawNode {
    pub tag: u64,
    pub xyz: [f64; 3],
    pub line: usize,
}

/// One element as read: its node tags are `RawMesh::conn[start..start + ty.n_nodes()]`.
pub(crate) struct RawElement {
    pub tag: u64,
    pub ty: element_types::GmshType,
    pub start: usize,
    /// Index into `RawMesh::phys_lists`: the physical tags the element belongs to.
    pub phys: usize,
    pub line: usize,
}

/// The file's contents before numbering and grouping.
#[derive(Default)]
pub(crate) struct RawMesh {
    pub nodes: Vec<RawNode>,
    pub elements: Vec<RawElement>,
    pub conn: Vec<u64>,
    /// Distinct lists of physical tags; index 0 is the empty list.
    pub phys_lists: Vec<Vec<i64>>,
    /// Physical names by (dimension, tag).
    pub names: HashMap<(i64, i64), String>,
}

impl RawMesh {
    pub fn new() -> Self {
        RawMesh {
            phys_lists: vec![Vec::new()],
            ..Default::default()
        }
    }

    /// Index of a physical-tag list in `phys_lists` (adds it when new).
    pub fn intern_phys(&mut self, tags: &[i64], index: &mut HashMap<Vec<i64>, usize>) -> usize {
        if tags.is_empty() {
            return 0;
        }
        if let Some(&i) = index.get(tags) {
            return i;
        }
        self.phys_lists.push(tags.to_vec());
        index.insert(tags.to_vec(), self.phys_lists.len() - 1);
        self.phys_lists.len() - 1
    }
}

enum Format {
    V22,
    V41 { binary: bool },
}

/// Reads `$MeshFormat` (which must come first) and checks version, file type and data size.
fn read_format(lines: &mut Lines) -> Result<Format, MeshError> {
    let first = lines
        .next_nonblank()?
        .ok_or_else(|| lines.err("empty file (expected `$MeshFormat`)"))?;
    if first.trim() != "$MeshFormat" {
        return Err(lines.err(format!(
            "expected `$MeshFormat` as the first line, found `{}` (not a gmsh .msh file?)",
            text::shorten(first)
        )));
    }
    let format_line = lines.expect_line("MeshFormat")?;
    let line = lines.line;
    let mut it = format_line.split_ascii_whitespace();
    let version = it.next().unwrap_or("").to_string();
    let file_type = it.next().unwrap_or("");
    let data_size = it.next().unwrap_or("");
    let file = lines.file;
    let unsupported = |reason: &str| MeshError::UnsupportedVersion {
        file: file.to_string(),
        line,
        version: version.clone(),
        reason: reason.to_string(),
    };
    let binary = match file_type {
        "0" => false,
        "1" => true,
        _ => {
            return Err(unsupported(&format!(
                "file-type `{file_type}` is not 0 or 1"
            )))
        }
    };
    if data_size != "8" {
        return Err(unsupported(&format!("data-size `{data_size}` is not 8")));
    }
    let format = match version.as_str() {
        "2" | "2.0" | "2.1" | "2.2" if !binary => Format::V22,
        "2" | "2.0" | "2.1" | "2.2" => {
            return Err(unsupported(
                "2.2 binary is not read; write msh41 binary or msh22 ASCII",
            ))
        }
        "4.1" => Format::V41 { binary },
        _ => return Err(unsupported("version not read")),
    };
    if binary {
        // One binary int 1, to detect the endianness, then a newline.
        let mut b = binary::Bin::new(lines.bytes, lines.pos, lines.file, line, "MeshFormat");
        let one = b.int("the endianness int")?;
        if one != 1 {
            return Err(unsupported(&format!(
                "the endianness int reads {one}, not 1 (big-endian file?)"
            )));
        }
        lines.advance_to(b.pos);
    }
    lines.expect_end("MeshFormat")?;
    Ok(format)
}
