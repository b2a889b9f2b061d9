//! One transient run of a prepared problem with either integrator, sampled on a time grid:
//! the engine of the work–precision study, of the hard-case suite and of the effects
//! benchmark. [`galpha_options`] also sets up `squeal transient` with
//! `integrator = "generalized_alpha"`.
//!
//! Nothing is written to disk: the only per-step work besides the integrator is the energy
//! bookkeeping, and only when asked for.

use crate::error::PipelineError;
use crate::scene::TransientSpec;
use crate::stages::transient::system::{GapFriction, Problem};
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_solver::bdf::Status;
use squeal_solver::bdf::{
    consistent_initial_conditions, Bdf, BdfOptions, InitialConditionOptions, TolerancePartition,
    Tolerances,
};
use squeal_solver::bsql::{steady_state, EnergyBalance, SteadyOptions};
use squeal_solver::galpha::{Galpha, GalphaOptions, GalphaSystem};
use squeal_solver::SolverError;

type Real = f64;

/// Integrator and accuracy setting of one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "integrator", rename_all = "snake_case")]
pub enum Method {
    /// BDF with RTOL1 = `rtol` (ATOL1 scaled by rtol / scene RTOL1) and MAXORD.
    Bdf { rtol: Real, max_order: usize },
    /// Generalized-α: fixed step `h`, or adaptive with `rtol` when `h` is None.
    GeneralizedAlpha {
        h: Option<Real>,
        rtol: Real,
        rho_inf: Real,
    },
}

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

fn solver_err(what: &str) -> impl FnOnce(SolverError) -> PipelineError + '_ {
    move |source| PipelineError::Solver {
        what: what.to_string(),
        source,
    }
}

/// Steady sliding state before the load and consistent y'(0), as `squeal transient` starts.
pub fn initial_state(
    problem: &Problem,
    gaps: &GapSet,
    tolint: Real,
) -> Result<(Vec<Real>, Vec<Real>), PipelineError> {
    let mut sys = problem.system(gaps.clone())?;
    let ss = steady_state(
        &mut sys,
        -1.0,
        &SteadyOptions {
            tol: tolint,
            ..Default::default()
        },
    )
    .map_err(solver_err("steady state"))?;
    let (mut y0, mut yp0) = ss.initial_values();
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions {
            tol: tolint,
            ..Default::default()
        },
    )
    .map_err(solver_err("consistent initial conditions"))?;
    Ok((y0, yp0))
}

/// Generalized-α options of a run on n DOFs and ng gaps: fixed step `h`, or adaptive with
/// RTOL1 = `rtol` (ATOL1 scaled by rtol / scene RTOL1) from `h0` or TFINAL/1000 when `h` is
/// None (`squeal transient` and the accuracy study both take them from here).
///
/// The Newton matrix always includes the friction damping C_f = ∂F_f/∂v: the scene's
/// `friction_damping_in_jacobian` is the BDF's (the paper's) choice. Without C_f the Newton
/// iteration in (q̈, λ') converges only linearly, at a rate ≈ c_v‖M⁻¹C_f‖ (c_v = γh(1−α_f)/(1−α_m))
/// that reaches 1 where contact points approach the stick zone of [Paper eq. (5)].
pub fn galpha_options(
    spec: &TransientSpec,
    n: usize,
    ng: usize,
    h: Option<Real>,
    rtol: Real,
    rho_inf: Real,
    tf: Real,
) -> GalphaOptions {
    // Fixed steps: the tolerances only set Newton's test; make it tight.
    let rtol = if h.is_some() { 1e-10 } else { rtol };
    let p = |len, rtol, atol| TolerancePartition { len, rtol, atol };
    let atol = spec.atol1 * rtol / spec.rtol1;
    GalphaOptions {
        rho_inf,
        h: h.or(spec.h0).unwrap_or(tf / 1000.0),
        adaptive: h.is_none(),
        tolerances: Tolerances::Partitions {
            parts: vec![
                p(n, rtol, atol),
                p(ng, spec.rtol2, spec.atol2),
                p(n, rtol, atol),
            ],
        },
        h_max: spec.h_max,
        max_steps: spec.max_steps,
        include_friction_damping: true,
        ..GalphaOptions::default()
    }
}

/// Advances through the grid times, recording the sampled values `advance` returns at each;
/// times ≤ 0 take `first` (the initial state). Returns the first status that is not `Reached`.
fn walk_grid(
    grid: &[Real],
    first: Vec<Real>,
    t_s: &mut Vec<Real>,
    v_s: &mut Vec<Vec<Real>>,
    mut advance: impl FnMut(Real) -> Result<(Status, Vec<Real>), PipelineError>,
) -> Result<Option<Status>, PipelineError> {
    for &tk in grid {
        if tk <= 0.0 {
            t_s.push(tk);
            v_s.push(first.clone());
            continue;
        }
        let (st, v) = advance(tk)?;
        if !st.is_success() {
            return Ok(Some(st));
        }
        t_s.push(tk);
        v_s.push(v);
    }
    Ok(None)
}

/// Integrates from (y0, y0') at t = 0 to the last grid time with `method`, sampling the
/// velocities of `dofs` at every grid time; `energy` also keeps the energy balance.
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    problem: &Problem,
    gaps: &GapSet,
    spec: &TransientSpec,
    method: Method,
    y0: &[Real],
    yp0: &[Real],
    grid: &[Real],
    dofs: &[usize],
    energy: bool,
) -> Result<RunOutcome, PipelineError> {
    let n = problem.m.nrows();
    let ng = problem.g.nrows();
    let mut obs = problem.system(gaps.clone())?;
    let scale = |rtol: Real| rtol / spec.rtol1;
    let mut balance = EnergyBalance::new();
    let mut drift: Real = 0.0;
    let gv0: Vec<Real> = (0..ng)
        .map(|k| (0..n).map(|j| problem.g[(k, j)] * y0[j]).sum())
        .collect();
    if energy {
        balance.push(&obs.observe(0.0, y0, yp0).map_err(solver_err("energy"))?);
    }
    let mut per_step = |t: Real, y: &[Real], yp: &[Real]| -> Result<bool, SolverError> {
        if energy {
            balance.push(&obs.observe(t, y, yp)?);
        }
        if ng > 0 {
            for (k, g0) in gv0.iter().enumerate() {
                let mut gv = 0.0;
                for j in 0..n {
                    gv += problem.g[(k, j)] * y[j];
                }
                drift = drift.max((gv - g0).abs());
            }
        }
        Ok(true)
    };
    let mut t_s = Vec::with_capacity(grid.len());
    let mut v_s = Vec::with_capacity(grid.len());
    let sample = |y: &[Real]| dofs.iter().map(|&d| y[d]).collect::<Vec<Real>>();
    let mut out = match method {
        Method::Bdf { rtol, max_order } => {
            let mut sys = problem.system(gaps.clone())?;
            let opts = BdfOptions {
                max_order,
                tolerances: sys.tolerances(rtol, spec.atol1 * scale(rtol), spec.rtol2, spec.atol2),
                h0: spec.h0,
                h_max: spec.h_max,
                max_steps: spec.max_steps,
                ..BdfOptions::default()
            };
            let mut bdf = Bdf::new(opts, 0.0, y0, yp0).map_err(solver_err("integrator"))?;
            let status = walk_grid(grid, sample(y0), &mut t_s, &mut v_s, |tk| {
                let st = bdf
                    .step_to(&mut sys, tk, |_, t, y, yp| per_step(t, y, yp))
                    .map_err(solver_err("integration"))?;
                Ok((st, sample(bdf.y())))
            })?;
            let s = bdf.stats();
            let bs = sys.stats();
            RunOutcome {
                method,
                reached: status.is_none(),
                status: status.unwrap_or(Status::Reached {
                    t: grid.last().copied().unwrap_or(0.0),
                }),
                t_end: bdf.t(),
                steps: s.steps,
                newton_iterations: s.newton_iterations,
                factorisations: bs.factorisations,
                residual_evals: s.residual_evals,
                rejected_steps: s.error_test_failures,
                cpu_s: s.cpu_s,
                max_constraint_drift: 0.0,
                energy: None,
                non_finite: false,
                t: Vec::new(),
                v: Vec::new(),
            }
        }
        Method::GeneralizedAlpha { h, rtol, rho_inf } => {
            let mut sys = GalphaSystem::new(
                problem.m.clone(),
                problem.b.clone(),
                problem.k.clone(),
                problem.g.clone(),
                problem.load.clone(),
                GapFriction { set: gaps.clone() },
            )
            .map_err(solver_err("building the generalized-alpha system"))?;
            let tf = grid.last().copied().unwrap_or(0.0);
            let opts = galpha_options(spec, n, ng, h, rtol, rho_inf, tf);
            let mut ga = Galpha::new(opts, &mut sys, 0.0, y0, yp0)
                .map_err(solver_err("generalized-alpha start"))?;
            let status = walk_grid(grid, sample(y0), &mut t_s, &mut v_s, |tk| {
                let st = ga
                    .step_to(&mut sys, tk, |_, t, y, yp| per_step(t, y, yp))
                    .map_err(solver_err("integration"))?;
                Ok((st, sample(ga.y())))
            })?;
            let s = ga.stats();
            RunOutcome {
                method,
                reached: status.is_none(),
                status: status.unwrap_or(Status::Reached {
                    t: grid.last().copied().unwrap_or(0.0),
                }),
                t_end: ga.t(),
                steps: s.steps,
                newton_iterations: s.newton_iterations,
                factorisations: s.factorisations,
                residual_evals: s.residual_evals,
                rejected_steps: s.rejected_steps,
                cpu_s: s.cpu_s,
                max_constraint_drift: 0.0,
                energy: None,
                non_finite: false,
                t: Vec::new(),
                v: Vec::new(),
            }
        }
    };
    out.max_constraint_drift = drift;
    out.energy = energy.then_some(balance);
    out.non_finite = v_s.iter().flatten().any(|x| !x.is_finite());
    out.t = t_s;
    out.v = v_s;
    Ok(out)
}
