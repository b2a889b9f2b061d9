//! The corrector: modified Newton iteration with a reused iteration matrix.
//!
//! # Reference
//! At t_n solve $G(y) = F(t_n, y, y'^{(0)} + c_j (y − y^{(0)})) = 0$ with
//! $J = ∂F/∂y + c_j ∂F/∂y'$ [Paper eq. (17)] formed at an earlier $c_j^{old}$. IDA's rules:
//! re-form J when $c_j/c_j^{old} ∉ [0.6, 1/0.6]$ (XRATE = 0.25: (1−0.25)/(1+0.25)), after a
//! convergence failure, or on the first step; scale each correction by $2/(1 + c_j/c_j^{old})$
//! to compensate the stale cj; at most 4 iterations; estimated rate
//! $ρ = (\|δ_m\|/\|δ_0\|)^{1/m}$ must stay below 0.9; converged when $\frac{ρ}{1−ρ}\|δ\| ≤ 0.33$
//! (the first iteration uses the previous step's ρ estimate, 20 after a set-up and 100 when cj
//! changed), or when $\|δ_0\| ≤ 10^{-4}·10^{-4}·0.33$.

use super::{Bdf, DaeSystem};
use crate::{Real, SolverError};

/// Outcome of a corrector attempt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Nls {
    Converged,
    /// Recoverable failure: retry with a smaller step.
    Failed,
}

/// Why a Newton iteration failed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum FailCause {
    /// Estimated rate above 0.9.
    Rate,
    /// Iteration limit reached.
    MaxIters,
    /// Non-finite values or a recoverable callback error.
    Other,
}

#[derive(Clone, Copy)]
enum SetupReason {
    Forced,
    CjRatio,
    StaleRetry,
}

const RATE_MAX: Real = 0.9;
const XRATE: Real = 0.25;

fn inf_norm(x: &[Real]) -> Real {
    let mut m: Real = 0.0;
    for v in x {
        if !v.is_finite() {
            return Real::NAN;
        }
        m = m.max(v.abs());
    }
    m
}

/// Map a callback error to a recoverable failure or propagate it.
fn recoverable(e: SolverError) -> Result<Nls, SolverError> {
    if e.is_recoverable() {
        Ok(Nls::Failed)
    } else {
        Err(e)
    }
}

impl Bdf {
    /// Evaluate F at (t_n, yy, yp) into delta; Failed on non-finite values.
    fn eval_residual<S: DaeSystem + ?Sized>(&mut self, sys: &mut S) -> Result<Nls, SolverError> {
        self.st.stats.residual_evals += 1;
        if let Err(e) = sys.residual(self.st.t, &self.w.yy, &self.w.yp, &mut self.w.delta) {
            self.w.last_res_norm = Real::NAN;
            return recoverable(e);
        }
        self.w.last_res_norm = inf_norm(&self.w.delta);
        if self.w.last_res_norm.is_nan() {
            return Ok(Nls::Failed);
        }
        Ok(Nls::Converged)
    }

    /// Predict, then iterate; on success yy, yp hold the corrected values and ee = yy − y⁽⁰⁾.
    pub(crate) fn nonlinear_solve<S: DaeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
    ) -> Result<Nls, SolverError> {
        let lo = (1.0 - XRATE) / (1.0 + XRATE);
        let mut call_setup = self.st.force_setup || self.st.jacobian_point.is_none();
        // Why a set-up is called, for the statistics.
        let mut reason = SetupReason::Forced;
        let cj_ratio = if self.st.cj_old > 0.0 {
            self.st.cj / self.st.cj_old
        } else {
            0.0
        };
        if !call_setup && (cj_ratio < lo || cj_ratio > 1.0 / lo) {
            call_setup = true;
            reason = SetupReason::CjRatio;
        }
        if self.st.cj != self.st.cj_last {
            self.st.ss = 100.0;
        }
        loop {
            super::coeffs::predict(&self.st, &mut self.w);
            if self.eval_residual(sys)? == Nls::Failed {
                return Ok(Nls::Failed);
            }
            if call_setup {
                self.st.stats.jacobian_setups += 1;
                match reason {
                    SetupReason::Forced => self.st.stats.setups_forced += 1,
                    SetupReason::CjRatio => self.st.stats.setups_cj_ratio += 1,
                    SetupReason::StaleRetry => self.st.stats.setups_stale_retry += 1,
                }
                self.st.force_setup = false;
                if self.form_matrix(sys)? == Nls::Failed {
                    return Ok(Nls::Failed);
                }
            }
            self.w.fail_cause = FailCause::Other;
            let out = self.newton_iterations(sys)?;
            if out == Nls::Failed && !call_setup {
                call_setup = true;
                reason = SetupReason::StaleRetry;
                continue;
            }
            if out == Nls::Failed {
                sys.newton_failed_with_fresh_matrix();
                match self.w.fail_cause {
                    FailCause::Rate => self.st.stats.convergence_failures_rate += 1,
                    FailCause::MaxIters => self.st.stats.convergence_failures_max_iters += 1,
                    FailCause::Other => {}
                }
            }
            return Ok(out);
        }
    }

    /// Remember where the iteration matrix is formed (for restarts), without allocating
    /// after the first time.
    fn record_jacobian_point(&mut self) {
        let (t, cj) = (self.st.t, self.st.cj);
        match &mut self.st.jacobian_point {
            Some(p) => {
                p.t = t;
                p.cj = cj;
                p.y.copy_from_slice(&self.w.yy);
                p.yp.copy_from_slice(&self.w.yp);
            }
            None => {
                self.st.jacobian_point = Some(super::JacobianPoint {
                    t,
                    cj,
                    y: self.w.yy.clone(),
                    yp: self.w.yp.clone(),
                })
            }
        }
    }

    /// The Newton loop proper; the residual at the prediction is in `delta`.
    fn newton_iterations<S: DaeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
    ) -> Result<Nls, SolverError> {
        let eps_newt = self.opts.newton_tol_coef;
        let tol_del = 1e-4 * eps_newt;
        let cj = self.st.cj;
        let cj_ratio = cj / self.st.cj_old;
        let scale = if cj_ratio != 1.0 {
            2.0 / (1.0 + cj_ratio)
        } else {
            1.0
        };
        let mut old_norm = 0.0;
        let mut m = 0usize;
        let mut scale = scale;
        // Set-ups of this attempt for a branch change (`DaeSystem::matrix_stale`), bounded so
        // that an iterate cycling between branches still fails.
        let mut branch_setups = 0usize;
        loop {
            self.st.stats.newton_iterations += 1;
            if let Err(e) = sys.solve_jacobian(&mut self.w.delta) {
                return recoverable(e);
            }
            if scale != 1.0 {
                for d in self.w.delta.iter_mut() {
                    *d *= scale;
                }
            }
            for i in 0..self.w.delta.len() {
                let d = self.w.delta[i];
                self.w.yy[i] -= d;
                self.w.ee[i] -= d;
                self.w.yp[i] -= cj * d;
            }
            let del_norm = super::error_test::wrms(&self.w.delta, &self.w);
            if !del_norm.is_finite() || !inf_norm(&self.w.delta).is_finite() {
                return Ok(Nls::Failed);
            }
            if m == 0 {
                old_norm = del_norm;
                if del_norm <= 1e-4 * tol_del {
                    return Ok(Nls::Converged);
                }
            } else {
                let rate = (del_norm / old_norm).powf(1.0 / m as Real);
                if rate > RATE_MAX {
                    if self.branch_setup(sys, &mut branch_setups)? {
                        (scale, m) = (1.0, 0);
                        continue;
                    }
                    self.w.fail_cause = FailCause::Rate;
                    return Ok(Nls::Failed);
                }
                self.st.ss = rate / (1.0 - rate);
            }
            if self.st.ss * del_norm <= eps_newt {
                return Ok(Nls::Converged);
            }
            m += 1;
            if m >= self.opts.max_newton_iters {
                if self.branch_setup(sys, &mut branch_setups)? {
                    (scale, m) = (1.0, 0);
                    continue;
                }
                self.w.fail_cause = FailCause::MaxIters;
                return Ok(Nls::Failed);
            }
            if self.eval_residual(sys)? == Nls::Failed {
                return Ok(Nls::Failed);
            }
        }
    }

    /// Before a Newton failure (too slow a rate or the iteration limit) at the iterate in
    /// `yy`: when the system says its matrix is of another branch than that iterate
    /// (`DaeSystem::matrix_stale`), the matrix is formed there and the attempt goes on — a
    /// semi-smooth Newton step, taken only when the matrix of the attempt's start does not
    /// converge (a stale branch that still converges costs nothing). Returns true when it
    /// did so (the residual at `yy` is then in `delta`).
    fn branch_setup<S: DaeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        count: &mut usize,
    ) -> Result<bool, SolverError> {
        if *count >= MAX_BRANCH_SETUPS || self.eval_residual(sys)? == Nls::Failed {
            return Ok(false);
        }
        if !sys.matrix_stale() {
            return Ok(false);
        }
        *count += 1;
        self.st.stats.jacobian_setups += 1;
        self.st.stats.setups_branch += 1;
        Ok(self.form_matrix(sys)? == Nls::Converged)
    }

    /// Forms and factorises the iteration matrix at (t, yy, yp) with the current cj and
    /// remembers where; Failed on a recoverable set-up failure (no matrix then).
    fn form_matrix<S: DaeSystem + ?Sized>(&mut self, sys: &mut S) -> Result<Nls, SolverError> {
        self.record_jacobian_point();
        if let Err(e) = sys.setup_jacobian(self.st.t, &self.w.yy, &self.w.yp, self.st.cj) {
            self.st.jacobian_point = None;
            return recoverable(e);
        }
        self.st.cj_old = self.st.cj;
        self.st.ss = 20.0;
        Ok(Nls::Converged)
    }
}

/// Largest number of set-ups for a branch change within one Newton attempt.
const MAX_BRANCH_SETUPS: usize = 8;
