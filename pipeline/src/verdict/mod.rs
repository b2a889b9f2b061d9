//! The squeal verdict, pure: series and settings in, a [`Verdict`] out ([`decide`]).
//!
//! Nothing here knows a sink, a scene, a run folder or an error: the run records the series
//! (the collectors), and this folder judges them.
//!
//! - [`roots`]: the response's roots (growth rate σ and frequency of each damped exponential)
//!   by a multi-channel matrix pencil;
//! - [`envelope`]: the growth and frequency of one DOF's envelope, the cross-check;
//! - [`fit`]: both on a recorded response over a window;
//! - [`limit_cycle`]: the stationary amplitude of the rotor face's normal velocity and where
//!   the response saturated into it (separation on);
//! - [`validity`]: what the contact did (tensile gaps);
//! - [`guard`]: a run says "no squeal" only when it could have seen squeal;
//! - [`decide`]: the steps above in order, the verdict of a run.

pub mod decide;
pub mod envelope;
pub mod fit;
pub mod guard;
pub mod limit_cycle;
pub mod outcome;
pub mod roots;
pub mod validity;

pub use decide::{decide, CeaRoots, Decision, Record, Settings};

pub use envelope::{analyse, slope, Envelope};
pub use fit::{fit, Series};
pub use outcome::{SquealEvidence, Verdict};

use serde::{Deserialize, Serialize};

/// The time integrator a run used: the guard models its numerical damping. The scene's
/// `transient.integrator` key names it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Variable-order, variable-step BDF in residual form (orders 1..=MAXORD).
    #[default]
    Bdf,
    /// Generalized-α (second order, numerical damping set by ρ∞).
    GeneralizedAlpha,
}

#[cfg(test)]
mod tests;
