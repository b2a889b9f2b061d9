//! Nastran bulk data (`.bdf`, `.dat`, `.nas`, `.blk`) into a [`Mesh`].
//!
//! Read: free, small and large field cards with continuations (`+`, `*`, blank first field),
//! `$` comments, `INCLUDE` (relative to the including file), `BEGIN BULK` / `ENDDATA` and the
//! case control's `SPC = n`; GRID (CP and CD in any system) and GRDSET; CORD1R/C/S and
//! CORD2R/C/S chained through their reference systems; CHEXA (8/20), CPENTA (6/15), CTETRA
//! (4/10), CPYRAM (5/13) mapped to squeal's node order ([`crate::mesh`]); PSOLID with its
//! material system CORDM; MAT1 and MAT9 (as [`crate::section::Section`]s); SPC, SPC1, SPCADD
//! and GRID PS as fixed DOFs; SET1 as node sets; CQUAD4/CQUAD8/CTRIA3/CTRIA6 as faces of the
//! solids (friction, load and fixed faces). Every other card is counted and listed in the
//! [`ReadReport`]: never skipped in silence.
//!
//! Names in the mesh: each solid property is a volume block and a node set `pid_<PID>` (its
//! section: `mesh.sections["pid_<PID>"]`); shells make the face set `pid_<PID>` of their
//! property; `set1_<SID>` and `spc_<SID>` are node sets. Node tags are the grid ids. A
//! mirrored element is reordered; a degenerate or folded one is an error. Errors name the file,
//! the line, the card and the id.

mod build;
mod card;
mod cards;
mod coords;
mod fields;
mod materials;
mod model;
mod spc;

use crate::deck::Deck;
use crate::import::ReadReport;
use crate::{Mesh, MeshError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What to read from a deck.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BdfOptions {
    /// Solid property ids to read (default: empty = every solid of the deck).
    pub pids: Vec<u64>,
    /// SPC set to apply: 0 none; default (None) the case control's `SPC = n`, else the deck's
    /// only set.
    pub spc: Option<u64>,
}

/// Reads the deck `path` (and its includes).
pub fn read_bdf(path: &Path, opts: &BdfOptions) -> Result<(Mesh, ReadReport), MeshError> {
    let mut deck = Deck::open(path)?;
    read(&mut deck, opts)
}

/// Parses a deck held in memory; `name` names it in errors, includes resolve against `dir`.
pub fn parse_bdf(
    bytes: &[u8],
    name: &str,
    dir: &Path,
    opts: &BdfOptions,
) -> Result<(Mesh, ReadReport), MeshError> {
    let mut deck = Deck::from_bytes(bytes.to_vec(), name, dir);
    read(&mut deck, opts)
}

fn read(deck: &mut Deck, opts: &BdfOptions) -> Result<(Mesh, ReadReport), MeshError> {
    let bulk = model::read_bulk(deck)?;
    build::build(bulk, deck, opts)
}

/// Every file the deck `path` reads (itself, then its includes in the order met), for a
/// cache key that changes when any of them does.
pub fn deck_files(path: &Path) -> Result<Vec<String>, MeshError> {
    let mut deck = Deck::open(path)?;
    cards::read_cards(&mut deck, |_, _| Ok(()))?;
    Ok(deck.files.clone())
}
