//! What a run does besides integrating: the [`Sink`] trait, the views sinks receive, and the
//! [`Checkpoint`] each sink saves its own state into at a restart point.
//!
//! The bottom of the transient wing: it imports nothing from its siblings. The views are plain
//! data (times, states, counters), not the stepper: a sink cannot reach into the integrator.
//! A checkpoint is a JSON object (`restart.json`'s `run`) in which every sink owns its keys —
//! a part at the top level or in a section (`records`) shared with others, each key written
//! once; a sink reads its part back with [`Saved::part`], ignoring the keys of others.

use crate::error::PipelineError;
pub use crate::problem::restart::{Checkpoint, Saved};
use squeal_solver::bdf::{BdfState, Status};
use squeal_solver::bsql::{EnergyBalance, PowerTerms};
use squeal_solver::Real;

/// One accepted step (or the initial point, `step` = the steps before the run) as sinks see it.
///
/// At a separation event the sinks see two views at the same time t: the state before the
/// switch (it ends the integrator's accepted step that crossed the event, cut back to the
/// event) and the state after it (switched rows, impact, consistent y'), which has
/// `repeat = true` and is no step: counters of steps skip it.
pub struct StepView<'a> {
    /// Accepted integrator steps so far, counted from the start of the integration (a
    /// restarted run continues its count); the state after an event does not add one.
    pub step: usize,
    /// This view is at the same time as the previous one: the state after an event, not an
    /// accepted step.
    pub repeat: bool,
    pub t: Real,
    /// y = {v, λ, u}.
    pub y: &'a [Real],
    /// y' = {v', λ', u'}.
    pub yp: &'a [Real],
    /// Energies at this point (when the run keeps the energy balance).
    pub power: Option<&'a PowerTerms>,
    /// The balance integrated so far (empty when not kept).
    pub balance: &'a EnergyBalance,
}

/// The end of a chunk of steps.
pub struct ChunkView<'a> {
    /// Time of the integrator's solution.
    pub t: Real,
    /// Accepted steps so far.
    pub steps: usize,
    /// The chunk ended in an error (sinks flush and write nothing new).
    pub failed: bool,
    /// The BDF's accepted steps by order so far (None for generalized-α).
    pub order_histogram: Option<&'a [u64]>,
}

/// The end of a run.
pub struct EndView<'a> {
    pub status: &'a Status,
    /// The solution where the integrator stopped (at TFINAL when it reached it).
    pub t: Real,
    pub y: &'a [Real],
    pub yp: &'a [Real],
    pub tfinal: Real,
    /// The BDF's accepted steps by order (None for generalized-α).
    pub order_histogram: Option<&'a [u64]>,
}

/// A restart point: the integrator's state and the checkpoint every sink saved into.
pub struct RestartPoint<'a> {
    /// Time of the state.
    pub t: Real,
    /// The BDF's complete state (None for generalized-α: no restart).
    pub state: Option<&'a BdfState>,
    pub checkpoint: &'a Checkpoint,
}

/// What a run does besides integrating. Every method but `step` has a default that does
/// nothing.
pub trait Sink {
    /// The initial point and every accepted step, in order.
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError>;
    /// True when the chunk should end after accepted step `step` (a restart is due).
    fn wants_break(&self, _step: usize) -> bool {
        false
    }
    /// The next time at which the sink wants the solution exactly (interpolated), if any.
    fn next_stop(&self) -> Option<Real> {
        None
    }
    /// The solution at a time `next_stop` asked for.
    fn stop(&mut self, _t: Real, _y: &[Real], _yp: &[Real]) -> Result<(), PipelineError> {
        Ok(())
    }
    /// After every chunk, also a failed one: flush.
    fn chunk_end(&mut self, _c: &ChunkView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    /// The run ended (any status).
    fn end(&mut self, _e: &EndView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    /// At a restart point (after the chunk ends where a sink wanted a break, and after the
    /// end), what this sink must carry over a restart: its own keys of the checkpoint.
    fn save(&self, _c: &mut Checkpoint) -> Result<(), PipelineError> {
        Ok(())
    }
    /// A restart point, after every sink saved its part (the restart writer writes it).
    fn restart_point(&mut self, _p: &RestartPoint<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
}
