//! Options of the complex eigenvalue analysis and of the friction sweep.

use super::CeaError;
use serde::{Deserialize, Serialize};

/// Complex eigenvalue analysis options. [Paper eqs. (19)–(24)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CeaOptions {
    /// A mode is unstable when Re p > `unstable_tol` × (largest |p| of the problem)
    /// (default: 1e-8; round-off on Re p is ~1e-16 |p|, and ~1e-8 |p| at a coalescence).
    pub unstable_tol: f64,
    /// G is rank deficient when σ_min(G)/σ_max(G) ≤ `rank_tol` (default: 1e-10).
    pub rank_tol: f64,
    /// Compute the mode shapes u = T q (default: true; false returns empty shapes).
    pub compute_shapes: bool,
}

impl Default for CeaOptions {
    fn default() -> Self {
        CeaOptions {
            unstable_tol: 1e-8,
            rank_tol: 1e-10,
            compute_shapes: true,
        }
    }
}

fn check(field: &'static str, v: f64, ok: bool, reason: &str) -> Result<(), CeaError> {
    if ok && v.is_finite() {
        Ok(())
    } else {
        Err(CeaError::InvalidOption {
            field,
            value: format!("{v}"),
            reason: reason.to_string(),
        })
    }
}

impl CeaOptions {
    /// Checks the options; the error names the field.
    pub fn validate(&self) -> Result<(), CeaError> {
        check(
            "cea.unstable_tol",
            self.unstable_tol,
            self.unstable_tol >= 0.0,
            "must be >= 0",
        )?;
        check(
            "cea.rank_tol",
            self.rank_tol,
            self.rank_tol >= 0.0 && self.rank_tol < 1.0,
            "must be in [0, 1)",
        )
    }
}

/// Friction sweep options (mode tracking and critical μ).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SweepOptions {
    /// Options of each eigenvalue solve (default: [`CeaOptions::default`]; shapes are always
    /// computed during a sweep since tracking needs them).
    pub cea: CeaOptions,
    /// Smallest MAC for two modes at neighbouring μ to be the same tracked mode; below it a
    /// track ends and a new one starts (default: 0.1).
    pub mac_min: f64,
    /// Refine each critical μ by bisection between the two steps that bracket it (default: true).
    pub bisection: bool,
    /// Bisection stops when the bracket is shorter than `bisection_tol`·max(1, |μ|)
    /// (default: 1e-7).
    pub bisection_tol: f64,
    /// Largest number of bisection solves per critical μ (default: 60).
    pub max_bisection: usize,
    /// Keep the mode shapes of every step in the result (default: false: memory n × modes × steps).
    pub keep_shapes: bool,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            cea: CeaOptions::default(),
            mac_min: 0.1,
            bisection: true,
            bisection_tol: 1e-7,
            max_bisection: 60,
            keep_shapes: false,
        }
    }
}

impl SweepOptions {
    /// Checks the options; the error names the field.
    pub fn validate(&self) -> Result<(), CeaError> {
        self.cea.validate()?;
        check(
            "sweep.mac_min",
            self.mac_min,
            (0.0..=1.0).contains(&self.mac_min),
            "must be in [0, 1]",
        )?;
        check(
            "sweep.bisection_tol",
            self.bisection_tol,
            self.bisection_tol > 0.0,
            "must be > 0",
        )
    }
}
