//! What the industrial readers (Nastran bulk data, Abaqus input) share: the report of what
//! was read, left out and changed, and the last step from file cells to a [`Mesh`] (orientation,
//! validity, node numbering, blocks, node and face sets).

mod build;
pub(crate) mod faces;

pub(crate) use build::{Builder, RawCell};

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What a reader found besides the mesh: counts, what it did not read, what it changed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ReadReport {
    /// `nastran` or `abaqus`.
    pub format: String,
    /// Every file read (the main file first, then the includes).
    pub files: Vec<String>,
    /// Entities read, by card or keyword (e.g. `GRID`, `CHEXA`, `*NODE`).
    pub counts: BTreeMap<String, usize>,
    /// Cards or keywords in the input that squeal does not read: each once, with its count.
    pub unsupported: Vec<Unsupported>,
    /// What squeal does differently from the file's solver or left out on purpose (e.g. C3D20R
    /// integrated with 27 points, rotational constraints on solid grids), one line each.
    pub notes: Vec<String>,
}

/// A card or keyword the reader does not read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Unsupported {
    /// The card name (`RBE2`) or keyword (`*TIE`).
    pub name: String,
    pub count: usize,
    /// `file:line` of its first occurrence.
    pub first: String,
}

impl ReadReport {
    /// One warning line for the unsupported cards, or None when every card was read.
    pub fn unsupported_summary(&self) -> Option<String> {
        if self.unsupported.is_empty() {
            return None;
        }
        let items: Vec<String> = self
            .unsupported
            .iter()
            .map(|u| format!("{} ×{} (first at {})", u.name, u.count, u.first))
            .collect();
        Some(format!("not read: {}", items.join(", ")))
    }
}
