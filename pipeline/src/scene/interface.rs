//! `[components.interface]`: the interface reduction of a rotor's contact boundary, at a fixed
//! polynomial degree or at the degree an error estimate of the in-band CEA roots chooses
//! (README "Interface reduction of a big rotor"; the choice: `model/degree.rs`).

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_solver::Real;

/// `[components.interface]`: the component's gap nodes (those not shared with another
/// component) are not Craig–Bampton boundary DOFs; per `[[contact]]` pair they move in an
/// orthonormal polynomial basis of the pair's rotor patch (Legendre polynomials of total
/// degree ≤ d in the patch's principal coordinates, per direction), and the gaps see
/// the rotor points through recovery rows over those interface coordinates.
///
/// Either `degree` alone (a fixed degree, no error estimate), or `tolerance` (with optional
/// `degree` to start from, `max_degree` and `step`): the degree rises by `step` until the
/// estimate of the in-band CEA roots' error is at most `tolerance`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    /// Highest total polynomial degree, 1..=30: the degree (without `tolerance`) or the first
    /// degree tried (with it; default 2). A flat patch has (d + 1)(d + 2)/2 functions per
    /// direction, fewer if it has fewer nodes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub degree: Option<usize>,
    /// Error estimate of the in-band CEA roots to reach (relative; `model/degree.rs`), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Real>,
    /// Highest degree tried with `tolerance`, ≤ 30 (default 16): not reaching the tolerance
    /// there is an error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_degree: Option<usize>,
    /// Degree increment with `tolerance` (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<usize>,
}

impl InterfaceSpec {
    /// Highest degree accepted.
    pub const MAX: usize = 30;
    /// First degree tried with `tolerance` when `degree` is not given.
    pub const DEFAULT_START: usize = 2;
    /// Highest degree tried with `tolerance` when `max_degree` is not given.
    pub const DEFAULT_MAX: usize = 16;
    /// Degree increment with `tolerance` when `step` is not given.
    pub const DEFAULT_STEP: usize = 2;

    /// The fixed degree, or the first degree tried with `tolerance`.
    pub fn start_degree(&self) -> usize {
        self.degree.unwrap_or(Self::DEFAULT_START)
    }

    /// Highest degree tried (the fixed degree without `tolerance`).
    pub fn max_degree(&self) -> usize {
        match self.tolerance {
            Some(_) => self.max_degree.unwrap_or(Self::DEFAULT_MAX),
            None => self.start_degree(),
        }
    }

    /// Degree increment.
    pub fn step(&self) -> usize {
        self.step.unwrap_or(Self::DEFAULT_STEP)
    }

    /// True when an error estimate chooses the degree.
    pub fn adaptive(&self) -> bool {
        self.tolerance.is_some()
    }

    /// Checks the keys of `components[i].interface`; the error names the key and its value.
    pub fn validate(&self, i: usize) -> Result<(), PipelineError> {
        let bad = |key: &str, message: String| PipelineError::Scene {
            field: format!("components[{i}].interface{key}"),
            message,
        };
        let Some(tol) = self.tolerance else {
            let Some(d) = self.degree else {
                return Err(bad(
                    "",
                    "give `degree` (a fixed degree) or `tolerance` (the degree an error \
                     estimate of the in-band CEA roots chooses)"
                        .into(),
                ));
            };
            for (key, set) in [("max_degree", self.max_degree), ("step", self.step)] {
                if let Some(v) = set {
                    return Err(bad(
                        &format!(".{key}"),
                        format!(
                            "{v} is read only with `tolerance`; `degree = {d}` alone is a fixed \
                             degree"
                        ),
                    ));
                }
            }
            return check_degree(d, ".degree", &bad);
        };
        if !(tol.is_finite() && tol > 0.0) {
            return Err(bad(
                ".tolerance",
                format!("{tol} must be a finite number > 0"),
            ));
        }
        let (start, max) = (self.start_degree(), self.max_degree());
        check_degree(start, ".degree", &bad)?;
        check_degree(max, ".max_degree", &bad)?;
        if max < start {
            return Err(bad(
                ".max_degree",
                format!("{max} is below the starting degree {start}"),
            ));
        }
        if self.step() == 0 {
            return Err(bad(".step", "0: the degree must rise by at least 1".into()));
        }
        Ok(())
    }
}

fn check_degree(
    d: usize,
    key: &str,
    bad: &impl Fn(&str, String) -> PipelineError,
) -> Result<(), PipelineError> {
    if (1..=InterfaceSpec::MAX).contains(&d) {
        Ok(())
    } else {
        Err(bad(
            key,
            format!("{d} is not in 1..={}", InterfaceSpec::MAX),
        ))
    }
}
