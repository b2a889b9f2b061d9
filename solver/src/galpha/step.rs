//! One generalized-α step: Newton on (q̈_{n+1}, f_{n+1}), the local error estimate and the
//! step-size control.
//!
//! # Newton
//! Three levels, each tried when the one before fails:
//! 1. modified Newton with the last matrix of `GalphaSystem::factor` (kept while h is
//!    unchanged; its friction tangents may be from an earlier step);
//! 2. the same from the predictor with the matrix re-formed there (fresh tangents);
//! 3. full Newton: the matrix re-formed at every iterate. Friction is non-smooth in the
//!    slip velocity (the arctangent of [Paper eq. (5)] has slope F_t/VTOL at zero slip,
//!    and the slip direction turns), so tangents at the predictor can be far from those at
//!    the solution when a contact point enters or leaves the stick zone; the iteration then
//!    only converges linearly (or not at all) with a matrix held fixed.
//!
//! IDA's convergence test on the implied corrections of y = {v, λ, u},
//! δy = (c_v δq̈, h/2 δf, c_u δq̈): the rate ρ = (‖δ_m‖/‖δ_0‖)^{1/m} must stay below 0.9,
//! and ρ/(1−ρ)‖δ‖ ≤ `newton_tol_coef`. Adaptive steps may stop after the first correction
//! on the rate estimated in earlier steps (20 after a factorisation), as IDA does, because
//! the error test follows; fixed steps have no error test, so their first correction is
//! always confirmed by a second (accepting it on a carried-over rate let steps into a stick
//! phase through unconverged, 8 % off in v on the stick–slip test).
//!
//! # Failed steps
//! Adaptive: the step is retried at h/4. Fixed step: the step [t_n, t_n + h] is covered by
//! substeps h/2, h/4, … (one halving per failure; the last substep ends exactly on
//! t_n + h), after which the run continues at h. It ends with
//! `Status::ConvergenceFailures` only after `max_failures` failures in a row or below
//! `h_min`. When h changes, a_n is moved to the new shift δh (below).
//!
//! # Local error estimate (adaptive steps)
//! From the Taylor expansion of the updates with a_n ≈ q̈(t_n + δh), δ = α_m − α_f
//! (constants in [`super::GalphaCoeffs::error_constants`]):
//! e_u = C_u h² (q̈_{n+1} − q̈_n) (Zienkiewicz–Xie's estimator generalised to α_m ≠ α_f),
//! e_v = C_v h³ q⁗ and e_λ = h³/12 f'' (trapezoidal rule), the last two with second divided
//! differences over (t_{n−1}, t_n, t_{n+1}) (not used on the first step). Accept when the
//! weighted RMS norm is ≤ 1; h_new = h·clamp(0.9·err^{−1/3}, 0.2, 2), increased only by
//! ≥ 1.5× and after 3 steps at the same h, to save factorisations, and decreased (to 0.8·factor·h) after
//! an accepted step whose error exceeds 0.85 (factor < 0.95). When h changes, a_n is moved to the new shift δh with
//! a_n += δ(h_new − h_old)·q⃛ (q⃛ from the last two accelerations).

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(err <= 1.0)` deliberately rejects NaN too.

use super::{Galpha, GalphaSystem, Status};
use crate::bdf::ATOL_EXCLUDED;
use crate::bsql::FrictionForces;
use crate::{Real, SolverError};

/// Outcome of one Newton attempt.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Nls {
    Converged,
    Failed,
}

/// Which matrix the Newton iteration uses.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Matrix {
    /// The last factorisation (same h, tangents possibly from an earlier step).
    Kept,
    /// Re-formed at the predictor.
    Fresh,
    /// Re-formed at every iterate (full Newton).
    Full,
}

const RATE_MAX: Real = 0.9;
/// Accepted steps at one h before the step size may grow.
const GROW_AFTER: u64 = 3;

fn recoverable(e: SolverError) -> Result<Nls, SolverError> {
    if e.is_recoverable() {
        Ok(Nls::Failed)
    } else {
        Err(e)
    }
}

impl Galpha {
    /// Error weights at the current point; returns the number of active components.
    fn set_weights(&mut self) -> usize {
        let (n, ng) = (self.cur.v.len(), self.cur.f.len());
        let w = &mut self.w;
        let mut active = 0;
        for i in 0..2 * n + ng {
            let y = if i < n {
                self.cur.v[i]
            } else if i < n + ng {
                self.cur.lam[i - n]
            } else {
                self.cur.u[i - n - ng]
            };
            w.ewt[i] = if w.atol[i] >= ATOL_EXCLUDED {
                0.0
            } else {
                active += 1;
                1.0 / (w.rtol[i] * y.abs() + w.atol[i])
            };
        }
        active.max(1)
    }

    /// Weighted RMS of the y-corrections implied by (δq̈, δf) = `delta`.
    fn correction_norm(&self, c_v: Real, c_u: Real, h: Real, active: usize) -> Real {
        let (n, ng) = (self.cur.v.len(), self.cur.f.len());
        let (d, e) = (&self.w.delta, &self.w.ewt);
        let mut s = 0.0;
        for i in 0..n {
            let dv = c_v * d[i] * e[i];
            let du = c_u * d[i] * e[n + ng + i];
            s += dv * dv + du * du;
        }
        for k in 0..ng {
            let dl = 0.5 * h * d[n + k] * e[n + k];
            s += dl * dl;
        }
        (s / active as Real).sqrt()
    }

    /// v, u (and a) of the trial point from its q̈.
    fn fill_trial(&mut self, c_v: Real, c_u: Real, c_a: Real) {
        let w = &self.w;
        let tr = &mut self.trial;
        for i in 0..tr.v.len() {
            tr.v[i] = w.v_base[i] + c_v * tr.qdd[i];
            tr.u[i] = w.u_base[i] + c_u * tr.qdd[i];
            tr.a[i] = w.a_base[i] + c_a * tr.qdd[i];
        }
    }

    fn eval_residual<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
    ) -> Result<Nls, SolverError> {
        self.stats.residual_evals += 1;
        let tr = &self.trial;
        if let Err(e) = sys.residual(tr.t, &tr.qdd, &tr.f, &tr.v, &tr.u, &mut self.w.delta) {
            self.w.last_res_norm = Real::NAN;
            return recoverable(e);
        }
        let mut m: Real = 0.0;
        for x in &self.w.delta {
            if !x.is_finite() {
                self.w.last_res_norm = Real::NAN;
                return Ok(Nls::Failed);
            }
            m = m.max(x.abs());
        }
        self.w.last_res_norm = m;
        Ok(Nls::Converged)
    }

    /// Newton from the predictor q̈ = q̈_n, f = f_n for a step of size h ending at `t_new`:
    /// the kept matrix, then a fresh one, then full Newton (see the module docs).
    fn attempt<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
        h: Real,
        t_new: Real,
        active: usize,
    ) -> Result<Nls, SolverError> {
        let co = self.co;
        let (am, af, g, b) = (co.alpha_m, co.alpha_f, co.gamma, co.beta);
        let c_a = co.c_a();
        let (c_v, c_u) = (h * g * c_a, h * h * b * c_a);
        let n = self.cur.v.len();
        self.trial.t = t_new;
        {
            let (c, w) = (&self.cur, &mut self.w);
            for i in 0..n {
                let ab = (af * c.qdd[i] - am * c.a[i]) / (1.0 - am);
                w.a_base[i] = ab;
                w.v_base[i] = c.v[i] + h * (1.0 - g) * c.a[i] + h * g * ab;
                w.u_base[i] = c.u[i] + h * c.v[i] + h * h * ((0.5 - b) * c.a[i] + b * ab);
            }
        }
        let mut matrix = if self.factored_h == Some(h) {
            Matrix::Kept
        } else {
            Matrix::Fresh
        };
        loop {
            self.trial.qdd.copy_from_slice(&self.cur.qdd);
            self.trial.f.copy_from_slice(&self.cur.f);
            self.fill_trial(c_v, c_u, c_a);
            if matrix != Matrix::Kept && self.refactor(sys, c_v, c_u, h)? == Nls::Failed {
                return Ok(Nls::Failed);
            }
            let out = self.newton(sys, c_v, c_u, c_a, h, active, matrix == Matrix::Full)?;
            if out == Nls::Failed && matrix != Matrix::Full {
                self.stats.convergence_failures += 1;
                matrix = match matrix {
                    Matrix::Kept => Matrix::Fresh,
                    _ => Matrix::Full,
                };
                continue;
            }
            if out == Nls::Converged {
                let (c, tr) = (&self.cur, &mut self.trial);
                for k in 0..tr.lam.len() {
                    tr.lam[k] = c.lam[k] + 0.5 * h * (c.f[k] + tr.f[k]);
                }
            }
            return Ok(out);
        }
    }

    /// Form and factorise the Newton matrix at the trial point (its v and f).
    fn refactor<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
        c_v: Real,
        c_u: Real,
        h: Real,
    ) -> Result<Nls, SolverError> {
        self.factored_h = None;
        self.stats.factorisations += 1;
        let tr = &self.trial;
        if let Err(e) = sys.factor(
            tr.t,
            &tr.v,
            &tr.f,
            c_v,
            c_u,
            self.opts.include_friction_damping,
        ) {
            return recoverable(e);
        }
        self.factored_h = Some(h);
        self.ss = 20.0;
        Ok(Nls::Converged)
    }

    /// Newton iterations from the trial point; `full` re-forms the matrix at every iterate
    /// after the first.
    #[allow(clippy::too_many_arguments)]
    fn newton<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
        c_v: Real,
        c_u: Real,
        c_a: Real,
        h: Real,
        active: usize,
        full: bool,
    ) -> Result<Nls, SolverError> {
        let n = self.cur.v.len();
        let coef = self.opts.newton_tol_coef;
        if self.eval_residual(sys)? == Nls::Failed {
            return Ok(Nls::Failed);
        }
        let mut old_norm = 0.0;
        let mut m = 0usize;
        loop {
            self.stats.newton_iterations += 1;
            if let Err(e) = sys.solve(&mut self.w.delta) {
                return recoverable(e);
            }
            let tr = &mut self.trial;
            for i in 0..n {
                tr.qdd[i] -= self.w.delta[i];
            }
            for k in 0..tr.f.len() {
                tr.f[k] -= self.w.delta[n + k];
            }
            self.fill_trial(c_v, c_u, c_a);
            let del = self.correction_norm(c_v, c_u, h, active);
            if !del.is_finite() {
                return Ok(Nls::Failed);
            }
            if m == 0 {
                old_norm = del;
                if del <= 1e-8 * coef {
                    return Ok(Nls::Converged);
                }
            } else {
                let rate = (del / old_norm).powf(1.0 / m as Real);
                if rate > RATE_MAX {
                    return Ok(Nls::Failed);
                }
                self.ss = rate / (1.0 - rate);
            }
            // Fixed steps have no error test to catch a step accepted on a rate carried over
            // from earlier steps: their first correction must be confirmed by a second.
            let confirmed = m > 0 || self.opts.adaptive;
            if confirmed && self.ss * del <= coef {
                return Ok(Nls::Converged);
            }
            m += 1;
            if m >= self.opts.max_newton_iters {
                return Ok(Nls::Failed);
            }
            if self.eval_residual(sys)? == Nls::Failed {
                return Ok(Nls::Failed);
            }
            if full {
                let ss = self.ss;
                if self.refactor(sys, c_v, c_u, h)? == Nls::Failed {
                    return Ok(Nls::Failed);
                }
                self.ss = ss;
            }
        }
    }

    /// Weighted RMS local error estimate of the converged trial step.
    fn error_norm(&self, h: Real, active: usize) -> Real {
        let (c_u, c_v) = self.co.error_constants();
        let (c, t, p) = (&self.cur, &self.trial, &self.prev);
        let (n, ng) = (c.v.len(), c.f.len());
        let e = &self.w.ewt;
        let hp = c.t - p.t;
        let second = self.has_prev && hp > 0.0;
        let dd = |y1: Real, y0: Real, ym: Real| 2.0 * ((y1 - y0) / h - (y0 - ym) / hp) / (h + hp);
        let mut s = 0.0;
        for i in 0..n {
            let eu = c_u * h * h * (t.qdd[i] - c.qdd[i]) * e[n + ng + i];
            s += eu * eu;
            if second {
                let ev = c_v * h * h * h * dd(t.qdd[i], c.qdd[i], p.qdd[i]) * e[i];
                s += ev * ev;
            }
        }
        if second {
            for k in 0..ng {
                let el = h * h * h / 12.0 * dd(t.f[k], c.f[k], p.f[k]) * e[n + k];
                s += el * el;
            }
        }
        (s / active as Real).sqrt()
    }

    /// Move the pseudo-acceleration of the current point to the shift of a step of size h.
    fn shift_pseudo_acceleration(&mut self, h: Real) {
        if !self.has_prev || h == self.a_h {
            self.a_h = h;
            return;
        }
        let d = self.co.delta() * (h - self.a_h) / (self.cur.t - self.prev.t);
        for i in 0..self.cur.a.len() {
            self.cur.a[i] += d * (self.cur.qdd[i] - self.prev.qdd[i]);
        }
        self.a_h = h;
    }

    /// One accepted step (a substep of a halved fixed step, or an adaptive step after its
    /// retries); `Some(status)` on failure.
    pub(crate) fn step<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
    ) -> Result<Option<Status>, SolverError> {
        if self.opts.adaptive {
            self.step_adaptive(sys)
        } else {
            self.step_fixed(sys)
        }
    }

    /// Fixed step h, on the grid t_base + k h; a step whose Newton iteration fails is
    /// covered by substeps h/2^j (j = `halvings`, one more per failure) ending on the grid.
    fn step_fixed<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
    ) -> Result<Option<Status>, SolverError> {
        let mut failures = 0usize;
        let active = self.set_weights();
        let target = self.t_base + (self.k_base + 1) as Real * self.h;
        loop {
            let t = self.cur.t;
            // The whole step is h itself (not target − t, which differs by round-off and
            // would re-form the matrix at every step).
            let sub = self.h / Real::powi(2.0, self.halvings as i32);
            let remaining = target - t;
            let (h, t_new, last) = if self.halvings == 0 {
                (self.h, target, true)
            } else if remaining <= sub * (1.0 + 1e-9) {
                (remaining, target, true)
            } else {
                (sub, t + sub, false)
            };
            self.shift_pseudo_acceleration(h);
            if self.attempt(sys, h, t_new, active)? == Nls::Converged {
                self.accept(sys, h);
                if last {
                    self.k_base += 1;
                    self.halvings = 0;
                }
                return Ok(None);
            }
            self.stats.convergence_failures += 1;
            failures += 1;
            if self.halvings == 0 {
                self.stats.halved_steps += 1;
            }
            self.halvings += 1;
            if failures >= self.opts.max_failures
                || 0.5 * h < self.opts.h_min.max(4.0 * Real::EPSILON * t.abs())
            {
                self.halvings = 0;
                return Ok(Some(Status::ConvergenceFailures {
                    t,
                    h,
                    order: 2,
                    residual_norm: self.w.last_res_norm,
                }));
            }
        }
    }

    /// Adaptive step: retried at h/4 after a Newton failure, at a smaller h after an error
    /// test failure; the next h from the error estimate.
    fn step_adaptive<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
    ) -> Result<Option<Status>, SolverError> {
        let mut failures = 0usize;
        let active = self.set_weights();
        loop {
            let h = self.h;
            let t = self.cur.t;
            if h < self.opts.h_min.max(4.0 * Real::EPSILON * t.abs()) {
                return Ok(Some(Status::StepSizeTooSmall {
                    t,
                    h,
                    order: 2,
                    residual_norm: self.w.last_res_norm,
                }));
            }
            self.shift_pseudo_acceleration(h);
            if self.attempt(sys, h, t + h, active)? == Nls::Failed {
                self.stats.convergence_failures += 1;
                failures += 1;
                if failures >= self.opts.max_failures {
                    return Ok(Some(Status::ConvergenceFailures {
                        t,
                        h,
                        order: 2,
                        residual_norm: self.w.last_res_norm,
                    }));
                }
                self.h = 0.25 * h;
                continue;
            }
            let err = self.error_norm(h, active);
            if !(err <= 1.0) {
                self.stats.rejected_steps += 1;
                failures += 1;
                if failures >= self.opts.max_failures {
                    return Ok(Some(Status::ErrorTestFailures {
                        t,
                        h,
                        order: 2,
                        error_norm: err,
                    }));
                }
                let fac = if err.is_finite() {
                    (0.9 * err.powf(-1.0 / 3.0)).clamp(0.2, 0.9)
                } else {
                    0.25
                };
                self.h = h * fac;
                continue;
            }
            let fac = if err > 0.0 {
                (0.9 * err.powf(-1.0 / 3.0)).min(2.0)
            } else {
                2.0
            };
            let h_max = self.opts.h_max.unwrap_or(Real::INFINITY);
            // Grow only after `GROW_AFTER` steps at this h without failures (as IDA
            // waits k + 1 steps): error estimates of single components pass through
            // zero twice per period and would invite growth followed by rejections.
            if fac >= 1.5 && failures == 0 && self.k_base + 1 >= GROW_AFTER {
                self.h = (h * fac).min(h_max);
            } else if fac < 0.95 {
                // Error close to the tolerance: shrink now, with a margin, rather than
                // be rejected next.
                self.h = h * (0.8 * fac).max(0.5);
            }
            // Steps at the same h (for `GROW_AFTER`).
            if self.h != h {
                self.k_base = 0;
            } else {
                self.k_base += 1;
            }
            self.accept(sys, h);
            return Ok(None);
        }
    }

    fn accept<F: FrictionForces>(&mut self, sys: &GalphaSystem<F>, h: Real) {
        std::mem::swap(&mut self.prev, &mut self.cur);
        self.cur.copy_from(&self.trial);
        self.has_prev = true;
        self.stats.steps += 1;
        self.stats.last_h = h;
        let drift = sys.drift(&self.cur.v, &self.w.g0);
        self.stats.constraint_drift = drift;
        self.stats.max_constraint_drift = self.stats.max_constraint_drift.max(drift);
    }
}
