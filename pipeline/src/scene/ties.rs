//! `[[ties]]`: bonded (glued) surfaces, inside a component or between two.

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_contact::{TieOptions, Unmatched};

use squeal_solver::Real;

/// One side of a tie: a face set of a component.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TieSide {
    /// Component name (required).
    pub component: String,
    /// Face set (physical surface) of the component (required).
    pub faces: String,
}

/// What a tie holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TieKind {
    /// Glued: every node of side `a` moves with the point of side `b` it is paired with, in
    /// all three directions (the default; sliding contact is a `[[contact]]` pair).
    #[default]
    Bonded,
}

/// How a tie pairs its sides (docs/pairing.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TiePairing {
    /// Each node of `a` projected on the faces of `b` (node-to-surface).
    Surface,
    /// Segment-to-segment with dual Lagrange multipliers on `a`'s faces: passes the patch
    /// test on any flat pair of meshes, a constant stress crosses the tie exactly (the
    /// default).
    #[default]
    Mortar,
}

/// A bonded tie between two face sets (`[[ties]]`): the nodes of side `a` (the slave side)
/// are expressed through the nodes of side `b` (the master side), u_a = Σ_b w u_b in x, y, z,
/// and eliminated. Inside one component (a component of several meshed bodies) before its
/// Craig–Bampton reduction; between two components after it, both sides' tied nodes being
/// boundary DOFs of their components.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TieSpec {
    /// The slave side (required): its nodes are eliminated; mesh it at least as finely as `b`.
    pub a: TieSide,
    /// The master side (required).
    pub b: TieSide,
    /// `"bonded"` (default: "bonded").
    #[serde(default)]
    pub kind: TieKind,
    /// `"mortar"` or `"surface"` (default: "mortar").
    #[serde(default)]
    pub pairing: TiePairing,
    /// Face extension ε of the projection, as in `[[contact]]` (default: 0.01).
    #[serde(default = "default_extension")]
    pub extension: Real,
    /// Largest distance from a node of `a` to side `b` (default: 0.05 × the mean edge length
    /// of `b`'s faces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_distance: Option<Real>,
}

fn default_extension() -> Real {
    TieOptions::default().extension
}

impl TieSpec {
    /// The pairing's options (every node of `a` must be tied: unmatched is an error).
    pub fn tie_options(&self) -> TieOptions {
        TieOptions {
            extension: self.extension,
            max_distance: self.max_distance,
            unmatched: Unmatched::Error,
        }
    }

    /// True when both sides are in one component.
    pub fn inside(&self) -> bool {
        self.a.component == self.b.component
    }

    /// Checks the values; errors name `ties[i].field`.
    pub fn validate(&self, i: usize) -> Result<(), PipelineError> {
        let bad = |field: &str, message: String| PipelineError::Scene {
            field: format!("ties[{i}].{field}"),
            message,
        };
        for (side, s) in [("a", &self.a), ("b", &self.b)] {
            if s.component.trim().is_empty() {
                return Err(bad(&format!("{side}.component"), "empty name".into()));
            }
            if s.faces.trim().is_empty() {
                return Err(bad(&format!("{side}.faces"), "empty face set name".into()));
            }
        }
        if self.a == self.b {
            return Err(bad(
                "b",
                format!(
                    "is side a (`{}` faces `{}`): a tie joins two different face sets",
                    self.a.component, self.a.faces
                ),
            ));
        }
        if !(self.extension.is_finite() && (0.0..=1.0).contains(&self.extension)) {
            return Err(bad(
                "extension",
                format!("{} must be in [0, 1]", self.extension),
            ));
        }
        if let Some(d) = self.max_distance {
            if !(d.is_finite() && d > 0.0) {
                return Err(bad("max_distance", format!("{d} must be finite and > 0")));
            }
        }
        Ok(())
    }
}
