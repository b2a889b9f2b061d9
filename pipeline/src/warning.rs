//! Warnings: input that squeal accepts but that the user may not have meant, with the measured
//! value (e.g. a stored stiffness that is slightly non-symmetric and was symmetrised).
//!
//! Library code never prints them: it returns them in its result (`ReducedModel::warnings`,
//! then the `warnings` of each verb's `summary.json`); the `squeal` command prints them to
//! stderr.

use serde::{Deserialize, Serialize};

use squeal_solver::Real;

/// One warning about an input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// The input: a file (and the matrix or line in it) or a scene key.
    pub input: String,
    /// What was found and what squeal did with it.
    pub message: String,
    /// The measured value.
    pub value: Real,
    /// The documented tolerance the value was compared with (above it the input is an error).
    pub tolerance: Real,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "warning: {}: {}", self.input, self.message)
    }
}
