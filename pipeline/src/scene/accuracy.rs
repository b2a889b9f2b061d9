//! `[accuracy]`: the tolerance and step ladders of the work–precision study.

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};

use squeal_solver::Real;

fn scene_err(field: &str, message: String) -> PipelineError {
    PipelineError::Scene {
        field: format!("accuracy.{field}"),
        message,
    }
}

/// `[accuracy]` table of a scene (`squeal accuracy`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AccuracySpec {
    /// RTOL1 ladder of the BDF runs (default: 1e-3, 1e-4, …, 1e-8). ATOL1 is scaled with it
    /// (ATOL1 · rtol / scene RTOL1).
    pub rtols: Vec<Real>,
    /// MAXORD values, each run with every rtol (default: [1, 2]).
    pub max_orders: Vec<usize>,
    /// Fixed steps of the generalized-α runs (default: none = derived from the reference run:
    /// its mean step × 4, 2, 1, 1/2, 1/4).
    pub galpha_steps: Option<Vec<Real>>,
    /// ρ∞ of the generalized-α runs (default: 0.9).
    pub rho_inf: Real,
    /// RTOL1 of the reference run, BDF at MAXORD = 2 (default: 1e-10).
    pub reference_rtol: Real,
    /// Number of points of the common time grid on [t_start, TFINAL] (default: 2000).
    pub samples: usize,
    /// Reduced DOF indices whose velocities are compared (default: empty = all DOFs).
    pub dofs: Vec<usize>,
    /// Repeat each run until this many seconds have passed and report the mean CPU time
    /// (default: 0 = one run).
    pub min_cpu_s: Real,
}

impl Default for AccuracySpec {
    fn default() -> Self {
        Self {
            rtols: vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8],
            max_orders: vec![1, 2],
            galpha_steps: None,
            rho_inf: 0.9,
            reference_rtol: 1e-10,
            samples: 2000,
            dofs: Vec::new(),
            min_cpu_s: 0.0,
        }
    }
}

impl AccuracySpec {
    /// Checks ranges; errors name `accuracy.field`.
    pub fn validate(&self) -> Result<(), PipelineError> {
        for (i, &r) in self.rtols.iter().enumerate() {
            if !(r.is_finite() && r > 0.0) {
                return Err(scene_err(
                    &format!("rtols[{i}]"),
                    format!("{r} must be > 0"),
                ));
            }
        }
        for (i, &o) in self.max_orders.iter().enumerate() {
            if !(1..=5).contains(&o) {
                return Err(scene_err(
                    &format!("max_orders[{i}]"),
                    format!("{o} must be in 1..=5"),
                ));
            }
        }
        for (i, &h) in self.galpha_steps.iter().flatten().enumerate() {
            if !(h.is_finite() && h > 0.0) {
                return Err(scene_err(
                    &format!("galpha_steps[{i}]"),
                    format!("{h} must be > 0"),
                ));
            }
        }
        if !(0.0..=1.0).contains(&self.rho_inf) {
            return Err(scene_err(
                "rho_inf",
                format!("{} must be in [0, 1]", self.rho_inf),
            ));
        }
        if !(self.reference_rtol.is_finite() && self.reference_rtol > 0.0) {
            return Err(scene_err(
                "reference_rtol",
                format!("{} must be > 0", self.reference_rtol),
            ));
        }
        if self.samples < 10 {
            return Err(scene_err(
                "samples",
                format!("{} must be >= 10", self.samples),
            ));
        }
        if !(self.min_cpu_s.is_finite() && self.min_cpu_s >= 0.0) {
            return Err(scene_err(
                "min_cpu_s",
                format!("{} must be >= 0", self.min_cpu_s),
            ));
        }
        Ok(())
    }
}
