//! Where a run starts: the steady sliding state before the brake load (TOLINT) and consistent
//! y'(0) ([`start_state`]), and the run's origin as a checkpoint part ([`Origin`]).

use super::options::start_options;
use super::sink::{Checkpoint, Saved, Sink, StepView};
use super::system::{solver_err, Problem};
use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_contact::GapSet;
use squeal_solver::bdf::{consistent_initial_conditions, IcStats};
use squeal_solver::bsql::steady_state;
use squeal_solver::Real;

/// Steady-state solve summary.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadySummary {
    pub iterations: usize,
    pub residual_norm: f64,
}

/// The start of a run without restart.
#[derive(Debug, Clone)]
pub struct StartState {
    pub y0: Vec<Real>,
    pub yp0: Vec<Real>,
    pub steady: SteadySummary,
    pub ic: IcStats,
}

/// The steady sliding state before the brake load (TOLINT) and consistent y'(0): the start of
/// every run that does not continue a restart (transient, accuracy study, hard cases).
pub fn start_state(
    problem: &Problem,
    gaps: &GapSet,
    tolint: Real,
) -> Result<StartState, PipelineError> {
    let mut sys = problem.system(gaps.clone())?;
    // t = −1 < 0: the ramp is 0, so the state is the sliding equilibrium under P0 alone.
    let (steady_opts, ic_opts) = start_options(tolint);
    let ss = steady_state(&mut sys, -1.0, &steady_opts).map_err(solver_err("steady state"))?;
    let (mut y0, mut yp0) = ss.initial_values();
    let ic = consistent_initial_conditions(&mut sys, 0.0, &mut y0, &mut yp0, None, &ic_opts)
        .map_err(solver_err("consistent initial conditions"))?;
    Ok(StartState {
        y0,
        yp0,
        steady: SteadySummary {
            iterations: ss.iterations,
            residual_norm: ss.residual_norm,
        },
        ic,
    })
}

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
