//! The time-history database: `history.npy` (float64, one row per recorded step: t, then the
//! records) and `history_map.json` (what each column is), as BSQL's binary database + map table.

pub mod npy;

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What a column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordKind {
    /// Time (column 0).
    Time,
    /// Grid displacement u (relative to the steady state at t = 0).
    Displacement,
    /// Grid velocity v.
    Velocity,
    /// Grid acceleration v'.
    Acceleration,
    /// Total compressive normal force of a gap, p_n·A = A·P_0 − λ̇. [Paper eq. (1)]
    ContactForce,
    /// Normal pressure p_n = −λ̇/A + P_0. [Paper eq. (1)]
    Pressure,
    /// Friction force magnitude after regularisation. [Paper eqs. (4)–(5)]
    FrictionForce,
    /// Total friction coefficient: friction force / normal force = μ·r(|V_t|) (μ with the
    /// arctangent regularisation of eq. (5) applied).
    FrictionCoefficient,
    /// Slip speed |V_t|. [Paper eq. (3)]
    SlipSpeed,
}

/// One column of `history.npy`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Column {
    /// Column index in the array.
    pub column: usize,
    /// Short unique name (`t`, `u_1000005_z`, `gap3_contact_force`).
    pub name: String,
    pub kind: RecordKind,
    /// Grid id (grid records).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<u64>,
    /// Direction x, y or z (grid records).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub component: Option<String>,
    /// Gap index (gap records).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<usize>,
    /// Reduced DOF index the record reads (grid records).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dof: Option<usize>,
}

/// `history_map.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HistoryMap {
    /// Number of columns.
    pub n_columns: usize,
    /// Every NOUTPT-th accepted step is recorded (plus the final time).
    pub noutpt: usize,
    pub columns: Vec<Column>,
}

impl HistoryMap {
    /// Reads `history_map.json`.
    pub fn read(path: &Path) -> Result<Self, PipelineError> {
        let text = std::fs::read_to_string(path).map_err(|source| PipelineError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        serde_json::from_str(&text).map_err(|e| PipelineError::Input {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }
}
