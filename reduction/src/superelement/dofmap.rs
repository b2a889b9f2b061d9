//! Global DOF keys and the map of the assembled reduced DOFs.

use crate::error::ReductionError;
use serde::{Deserialize, Serialize};

/// A physical DOF identified as in NASTRAN: grid id and component 1..6
/// (1–3 translations x, y, z; 4–6 rotations).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct DofKey {
    pub grid: u64,
    pub comp: u8,
}

impl DofKey {
    /// Key of grid `grid`, component `comp` (1..6); the error names the bad component.
    pub fn new(grid: u64, comp: u8) -> Result<Self, ReductionError> {
        if !(1..=6).contains(&comp) {
            return Err(ReductionError::Superelement {
                component: format!("grid {grid}"),
                detail: format!("DOF component {comp} is not in 1..6"),
            });
        }
        Ok(Self { grid, comp })
    }
}

/// What one reduced DOF is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum DofKind {
    /// A physical boundary DOF.
    Grid { grid: u64, comp: u8 },
    /// Modal coordinate `index` (0-based) of its component's fixed-interface modes.
    Modal { index: usize },
    /// Interface coordinate `index` (0-based) of its component's interface basis: the grid
    /// DOFs of the interface are recovered from these ([`ReducedDofMap::recovered`]).
    Interface { index: usize },
}

/// A grid DOF that is not a reduced DOF but a combination of them (the interface DOFs of an
/// interface-reduced component): u = Σ_k `coefs[k]` · x[`dofs[k]`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecoveredDof {
    pub component: String,
    pub grid: u64,
    pub comp: u8,
    /// Reduced DOF indices.
    pub dofs: Vec<usize>,
    /// Their coefficients.
    pub coefs: Vec<f64>,
}

/// One DOF of the assembled reduced system.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReducedDof {
    /// Component the DOF belongs to (the first one, for shared grid DOFs).
    pub component: String,
    /// Other components sharing this grid DOF.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shared_with: Vec<String>,
    #[serde(flatten)]
    pub kind: DofKind,
}

/// The DOF map of an assembled reduced system: row/column i of K, M, B is `dofs[i]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReducedDofMap {
    pub dofs: Vec<ReducedDof>,
    /// Grid DOFs recovered from the reduced DOFs (empty without interface reduction).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub recovered: Vec<RecoveredDof>,
}

impl ReducedDofMap {
    /// Number of reduced DOFs.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }
    /// Index of the grid DOF `key`, if it is in the assembly.
    pub fn index_of_grid(&self, key: DofKey) -> Option<usize> {
        self.dofs.iter().position(|d| {
            d.kind
                == DofKind::Grid {
                    grid: key.grid,
                    comp: key.comp,
                }
        })
    }
    /// The map of `dofs`, with no recovered grid DOFs.
    pub fn new(dofs: Vec<ReducedDof>) -> Self {
        Self {
            dofs,
            recovered: Vec::new(),
        }
    }
    /// JSON text of the map (to be written next to OP4 files).
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        serde_json::to_string_pretty(self)
    }
    /// Reads a map written by [`ReducedDofMap::to_json`].
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }
}
