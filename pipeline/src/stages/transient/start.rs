//! The run's origin as a checkpoint part ([`Origin`]): its start time, steady state and
//! initial conditions.

use super::sink::{Checkpoint, Saved, Sink, StepView};
use crate::error::PipelineError;
pub use crate::problem::start::{start_state, StartState, SteadySummary};
use serde::{Deserialize, Serialize};
use squeal_solver::bdf::IcStats;
use squeal_solver::Real;

/// Where the run started — its start time, steady state and initial conditions — a sink that
/// only carries them over restarts (top-level keys of the checkpoint).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Origin {
    /// Start time of the whole run (before any restart).
    pub t_start: Real,
    /// The steady state and initial conditions the run started from.
    pub steady_state: Option<SteadySummary>,
    pub initial_conditions: Option<IcStats>,
}

impl Origin {
    /// The origin saved in a checkpoint: a start time at or before the state's.
    pub fn restore(s: &Saved<'_>) -> Result<Self, PipelineError> {
        let o: Origin = s.part(None)?;
        if !o.t_start.is_finite() || o.t_start > s.t {
            return Err(s.bad(
                "t_start",
                format!("{} is not a start time at or before t = {}", o.t_start, s.t),
            ));
        }
        Ok(o)
    }
}

impl Sink for Origin {
    fn step(&mut self, _: &StepView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    fn save(&self, c: &mut Checkpoint) -> Result<(), PipelineError> {
        c.save(None, self)
    }
}
