//! Where a run starts: the steady sliding state before the brake load (TOLINT) and consistent
//! y'(0) ([`start_state`]).

use super::options::start_options;
use super::system::{solver_err, Problem};
use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
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
pub fn start_state(problem: &Problem, tolint: Real) -> Result<StartState, PipelineError> {
    let mut sys = problem.system(problem.gaps.clone())?;
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
