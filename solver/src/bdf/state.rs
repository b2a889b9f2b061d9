//! The integrator's serialisable state and statistics.
//!
//! Everything the next step depends on lives in [`BdfState`]: the modified divided
//! differences, the step history, the Newton bookkeeping, and the point at which the last
//! iteration matrix was formed. Restoring the state re-forms that matrix at the same point,
//! so a restarted run repeats the uninterrupted one step for step.

use serde::{Deserialize, Serialize};

use crate::Real;

/// Counters of one integration (written to `summary.json`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BdfStats {
    /// Accepted steps.
    pub steps: u64,
    /// Newton iterations (linear solves with the iteration matrix).
    pub newton_iterations: u64,
    /// Residual evaluations.
    pub residual_evals: u64,
    /// Iteration-matrix set-ups (factorisations).
    pub jacobian_setups: u64,
    /// Local error test failures.
    pub error_test_failures: u64,
    /// Newton convergence failures (including recoverable callback failures).
    pub convergence_failures: u64,
    /// Accepted steps per order: `order_histogram[k]` counts steps taken at order k.
    pub order_histogram: Vec<u64>,
    /// Size of the last accepted step.
    pub last_h: Real,
    /// Order of the last accepted step.
    pub last_order: usize,
    /// Wall-clock seconds spent inside `step_to`, the per-step callback (the caller's
    /// bookkeeping) excluded (named cpu_s as in BSQL's table).
    pub cpu_s: Real,
    /// Set-ups because cj left [0.6, 1/0.6] × the cj of the last set-up (IDA's rule).
    #[serde(default)]
    pub setups_cj_ratio: u64,
    /// Set-ups forced by a convergence failure of the step before (and the first step).
    #[serde(default)]
    pub setups_forced: u64,
    /// Set-ups because Newton failed with an older matrix and is retried with a fresh one.
    #[serde(default)]
    pub setups_stale_retry: u64,
    /// Set-ups within a Newton attempt because its iterate crossed to another branch of a
    /// piecewise law (`DaeSystem::matrix_stale`).
    #[serde(default)]
    pub setups_branch: u64,
    /// Convergence failures (with a fresh matrix) whose estimated rate exceeded 0.9.
    #[serde(default)]
    pub convergence_failures_rate: u64,
    /// Convergence failures (with a fresh matrix) at the iteration limit.
    #[serde(default)]
    pub convergence_failures_max_iters: u64,
}

/// The (t, y, y', cj) at which the current iteration matrix was formed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JacobianPoint {
    /// Time.
    pub t: Real,
    /// Coefficient cj of ∂F/∂y'.
    pub cj: Real,
    /// State.
    pub y: Vec<Real>,
    /// Derivative.
    pub yp: Vec<Real>,
}

/// Complete, serialisable integrator state (IDA's memory minus scratch vectors).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BdfState {
    /// System size.
    pub n: usize,
    /// Current internal time t_n.
    pub t: Real,
    /// Step size for the next step.
    pub h: Real,
    /// Order for the next step (IDA's kk).
    pub order: usize,
    /// Order of the last accepted step (kused; 0 before the first step).
    pub k_used: usize,
    /// Size of the last accepted step (hused).
    pub h_used: Real,
    /// Number of steps taken with the current h and order (ns).
    pub ns: usize,
    /// Start-up phase 0 (order raised and h doubled each step) or 1.
    pub phase: u8,
    /// True until the first step size has been chosen and phi[1] scaled by it.
    pub h_pending: bool,
    /// Leading coefficient cj = −αs/h of the current step.
    pub cj: Real,
    /// cj at the last matrix set-up.
    pub cj_old: Real,
    /// cj of the previous step.
    pub cj_last: Real,
    /// Convergence-rate estimate factor ss = rate/(1 − rate).
    pub ss: Real,
    /// Force a matrix set-up on the next attempt.
    pub force_setup: bool,
    /// ψ_i = t_n − t_{n−i−1} (length max_order + 1).
    pub psi: Vec<Real>,
    /// α_i coefficients.
    pub alpha: Vec<Real>,
    /// β_i coefficients.
    pub beta: Vec<Real>,
    /// σ_i coefficients.
    pub sigma: Vec<Real>,
    /// γ_i coefficients.
    pub gamma: Vec<Real>,
    /// Modified divided differences φ_0..φ_{max_order+1}, each of length n.
    pub phi: Vec<Vec<Real>>,
    /// y' at t_n (last accepted step, or y0').
    pub yp: Vec<Real>,
    /// Where the current iteration matrix was formed (None: none yet).
    pub jacobian_point: Option<JacobianPoint>,
    /// Counters so far.
    pub stats: BdfStats,
    /// `stats.steps` at the last (re)start: the start-up phase counts steps from here
    /// (0 unless [`super::Bdf::reinit`] restarted the integration at an event).
    #[serde(default)]
    pub start_step: u64,
    /// The (re)start was warm ([`super::Bdf::reinit_taylor`]): the difference arrays already
    /// hold an order-2 past, so the first step is not a cold start (false for a cold start).
    #[serde(default)]
    pub warm: bool,
    /// Consecutive accepted steps shorter than `BdfOptions::h_collapse` (kept over restarts).
    #[serde(default)]
    pub collapse_count: u64,
}

impl BdfState {
    /// Steps accepted since the last (re)start.
    pub(crate) fn steps_since_start(&self) -> u64 {
        self.stats.steps.saturating_sub(self.start_step)
    }

    /// No step since a cold (re)start: the difference arrays hold y and y' only (φ_1 = y' until
    /// h is chosen, then h y'), and the first step is of order 1.
    pub(crate) fn cold_start(&self) -> bool {
        self.steps_since_start() == 0 && !self.warm
    }
}

impl BdfState {
    /// Fresh state at (t0, y0, y0') for orders up to `max_order`.
    pub(crate) fn new(t0: Real, y0: &[Real], yp0: &[Real], max_order: usize) -> Self {
        let n = y0.len();
        let m = max_order + 2;
        let mut phi = vec![vec![0.0; n]; m];
        phi[0].copy_from_slice(y0);
        // phi[1] holds y0' until the first step size is known, then h·y0'.
        phi[1].copy_from_slice(yp0);
        Self {
            n,
            t: t0,
            h: 0.0,
            order: 1,
            k_used: 0,
            h_used: 0.0,
            ns: 0,
            phase: 0,
            h_pending: true,
            cj: 0.0,
            cj_old: 0.0,
            cj_last: 0.0,
            ss: 20.0,
            force_setup: true,
            psi: vec![0.0; m],
            alpha: vec![0.0; m],
            beta: vec![0.0; m],
            sigma: vec![0.0; m],
            gamma: vec![0.0; m],
            phi,
            yp: yp0.to_vec(),
            jacobian_point: None,
            stats: BdfStats {
                order_histogram: vec![0; max_order + 1],
                ..Default::default()
            },
            start_step: 0,
            warm: false,
            collapse_count: 0,
        }
    }
}
