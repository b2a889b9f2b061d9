//! One transient run of a prepared problem with either integrator, sampled on a time grid:
//! the engine of the work–precision study, of the hard-case suite and of the effects
//! benchmark. [`galpha_options`] also sets up `squeal transient` with
//! `integrator = "generalized_alpha"`.
//!
//! Nothing is written to disk: the only per-step work besides the integrator is the energy
//! bookkeeping, and only when asked for.

use crate::error::PipelineError;
pub use crate::problem::options::galpha_options;
use crate::problem::start::start_state;
use crate::problem::system::Problem;
use crate::progress::Progress;
use crate::scene::TransientSpec;
use crate::stages::transient::driver::{drive, DriveOptions};
use crate::stages::transient::sink::{Sink, StepView};
pub use crate::stages::transient::stepper::Method;
use crate::stages::transient::stepper::{IntegratorStats, Stepper};
use serde::Serialize;
use squeal_solver::bdf::Status;
use squeal_solver::bsql::EnergyBalance;

use squeal_solver::Real;

/// What one run gave.
#[derive(Debug, Clone, Serialize)]
pub struct RunOutcome {
    pub method: Method,
    /// `reached`, or the integrator's status with t, h and order (2 for generalized-α).
    pub status: Status,
    pub reached: bool,
    /// Time reached.
    pub t_end: Real,
    pub steps: u64,
    pub newton_iterations: u64,
    pub factorisations: u64,
    pub residual_evals: u64,
    pub rejected_steps: u64,
    /// Seconds inside the integrator (its own `cpu_s` counter).
    pub cpu_s: Real,
    /// Largest ‖G v − G v₀‖∞ over the steps.
    pub max_constraint_drift: Real,
    /// Energy balance (only when asked for).
    pub energy: Option<EnergyBalance>,
    /// True when a sample is NaN or infinite.
    pub non_finite: bool,
    /// Sample times (the grid up to `t_end`).
    #[serde(skip)]
    pub t: Vec<Real>,
    /// Velocities of the chosen DOFs at the sample times: `v[k][j]` = DOF j at t[k].
    #[serde(skip)]
    pub v: Vec<Vec<Real>>,
}

/// Steady sliding state before the load and consistent y'(0), as `squeal transient` starts.
pub fn initial_state(
    problem: &Problem,
    tolint: Real,
) -> Result<(Vec<Real>, Vec<Real>), PipelineError> {
    let s = start_state(problem, tolint)?;
    Ok((s.y0, s.yp0))
}

/// Samples the velocities of the chosen DOFs at the grid times (each integrator interpolates
/// its own solution there).
struct GridSampler<'a> {
    grid: &'a [Real],
    dofs: &'a [usize],
    next: usize,
    started: bool,
    t: Vec<Real>,
    v: Vec<Vec<Real>>,
}

impl GridSampler<'_> {
    fn take(&mut self, t: Real, y: &[Real]) {
        self.t.push(t);
        self.v.push(self.dofs.iter().map(|&d| y[d]).collect());
        self.next += 1;
    }
}

impl Sink for GridSampler<'_> {
    /// The initial point serves every grid time up to the start.
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        if !self.started {
            self.started = true;
            while self.grid.get(self.next).is_some_and(|&tk| tk <= s.t) {
                self.take(self.grid[self.next], s.y);
            }
        }
        Ok(())
    }
    fn next_stop(&self) -> Option<Real> {
        self.grid.get(self.next).copied()
    }
    fn stop(&mut self, t: Real, y: &[Real], _yp: &[Real]) -> Result<(), PipelineError> {
        self.take(t, y);
        Ok(())
    }
}

/// Largest ‖G v − G v₀‖∞ over the accepted steps.
struct DriftMonitor<'a> {
    g: &'a faer::Mat<Real>,
    gv0: Vec<Real>,
    max: Real,
}

impl Sink for DriftMonitor<'_> {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        let n = self.g.ncols();
        for (k, g0) in self.gv0.iter().enumerate() {
            let gv: Real = (0..n).map(|j| self.g[(k, j)] * s.y[j]).sum();
            self.max = self.max.max((gv - g0).abs());
        }
        Ok(())
    }
}

/// Integrates from (y0, y0') at t = 0 to the last grid time with `method`, sampling the
/// velocities of `dofs` at every grid time; `energy` also keeps the energy balance.
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    problem: &Problem,
    spec: &TransientSpec,
    method: Method,
    y0: &[Real],
    yp0: &[Real],
    grid: &[Real],
    dofs: &[usize],
    energy: bool,
) -> Result<RunOutcome, PipelineError> {
    let n = problem.m.nrows();
    let tf = grid.last().copied().unwrap_or(0.0);
    let mut stepper = Stepper::new(problem, spec, method, 0.0, y0, yp0, tf)?;
    let mut sampler = GridSampler {
        grid,
        dofs,
        next: 0,
        started: false,
        t: Vec::with_capacity(grid.len()),
        v: Vec::with_capacity(grid.len()),
    };
    let mut drift = DriftMonitor {
        g: &problem.g,
        gv0: (0..problem.g.nrows())
            .map(|k| (0..n).map(|j| problem.g[(k, j)] * y0[j]).sum())
            .collect(),
        max: 0.0,
    };
    let out = drive(
        &mut stepper,
        &mut [&mut sampler, &mut drift],
        &DriveOptions {
            tfinal: tf,
            max_steps: spec.max_steps,
            energy,
            label: "accuracy run".into(),
        },
        &Progress::quiet(),
    )?;
    let (newton_iterations, factorisations, residual_evals, rejected_steps) = match stepper.stats()
    {
        IntegratorStats::Bdf { bdf, bsql, .. } => (
            bdf.newton_iterations,
            bsql.factorisations,
            bdf.residual_evals,
            bdf.error_test_failures,
        ),
        IntegratorStats::GeneralizedAlpha { galpha } => (
            galpha.newton_iterations,
            galpha.factorisations,
            galpha.residual_evals,
            galpha.rejected_steps,
        ),
    };
    let stats = stepper.stats();
    let reached = out.status.is_success();
    Ok(RunOutcome {
        method,
        reached,
        status: out.status,
        t_end: out.t_end,
        steps: stats.steps(),
        newton_iterations,
        factorisations,
        residual_evals,
        rejected_steps,
        cpu_s: stats.cpu_s(),
        max_constraint_drift: drift.max,
        non_finite: sampler.v.iter().flatten().any(|x| !x.is_finite()),
        energy: out.energy,
        t: sampler.t,
        v: sampler.v,
    })
}
