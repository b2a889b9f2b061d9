//! Abaqus input (`.inp`) into a [`Mesh`].
//!
//! Read: `**` comments, keyword lines with parameters (case-insensitive, continued by a
//! trailing comma), data lines (continued by a trailing comma), `*INCLUDE` (relative to the
//! including file); *NODE (SYSTEM=R or C), *ELEMENT (C3D4, C3D10, C3D6, C3D15, C3D8, C3D8I,
//! C3D8R, C3D20, C3D20R; their node order is squeal's), *NSET and *ELSET (labels, set names,
//! GENERATE, ELSET=, INSTANCE=), *SURFACE (TYPE=ELEMENT with S1…S6 or the free faces of a set;
//! TYPE=NODE), *MATERIAL with *ELASTIC (ISOTROPIC, ENGINEERING CONSTANTS, ORTHOTROPIC,
//! ANISOTROPIC) and *DENSITY, *SOLID SECTION with *ORIENTATION (RECTANGULAR, CYLINDRICAL;
//! COORDINATES or NODES), *PART / *ASSEMBLY / *INSTANCE with its translation and rotation,
//! and zero-valued *BOUNDARY conditions (model data or steps) as fixed DOFs. Every other
//! keyword is counted and listed in the [`ReadReport`]; keywords that would move or generate
//! nodes (*NCOPY, *NGEN, *SYSTEM, …) are errors.
//!
//! Names in the mesh: volume blocks are named after their section's element set (or the
//! *ELEMENT line's ELSET when the file has no sections); node sets from *NSET, and from *ELSET
//! under the same name; face sets from *SURFACE; with several instances read, part-level
//! names get the prefix `instance.`. Node tags are the labels (offset per instance when
//! several are read). Errors name the file, the line and the entity.

mod build;
mod elements;
mod keywords;
mod materials;
mod model;
mod named;
mod sets;

use crate::deck::Deck;
use crate::import::ReadReport;
use crate::{Mesh, MeshError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What to read from an input file.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InpOptions {
    /// Instances to read (default: empty = every instance, or the part / model level of a
    /// file without an assembly).
    pub instances: Vec<String>,
    /// Read the instances of this part only (default: None = any part).
    pub part: Option<String>,
    /// Element sets to read, within the selected instances (default: empty = every element).
    pub elsets: Vec<String>,
}

/// Reads the input file `path` (and its includes).
pub fn read_inp(path: &Path, opts: &InpOptions) -> Result<(Mesh, ReadReport), MeshError> {
    let mut deck = Deck::open(path)?;
    read(&mut deck, opts)
}

/// Parses an input file held in memory; `name` names it in errors, includes resolve against
/// `dir`.
pub fn parse_inp(
    bytes: &[u8],
    name: &str,
    dir: &Path,
    opts: &InpOptions,
) -> Result<(Mesh, ReadReport), MeshError> {
    let mut deck = Deck::from_bytes(bytes.to_vec(), name, dir);
    read(&mut deck, opts)
}

fn read(deck: &mut Deck, opts: &InpOptions) -> Result<(Mesh, ReadReport), MeshError> {
    let m = model::read_model(deck)?;
    build::build(m, deck, opts)
}

/// Every file the input `path` reads (itself, then its includes in the order met), for a
/// cache key that changes when any of them does.
pub fn input_files(path: &Path) -> Result<Vec<String>, MeshError> {
    let mut deck = Deck::open(path)?;
    keywords::read_blocks(&mut deck, |_, _| Ok(()))?;
    Ok(deck.files.clone())
}
