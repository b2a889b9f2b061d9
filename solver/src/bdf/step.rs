//! One BDF step: attempt, error test, failure recovery, and the step/order selection after
//! an accepted step (IDA's IDAStep, IDAHandleNFlag and IDACompleteStep, re-derived).

use super::coeffs::{restore, set_coefficients};
use super::error_test::{after_convergence_failure, after_error_failure, test_error, wrms};
use super::newton::Nls;
use super::{Bdf, DaeSystem, Status};
use crate::{Real, SolverError};

impl Bdf {
    /// Take one step. `Ok(None)` on success (state advanced, φ updated, y' stored);
    /// `Ok(Some(status))` when the step cannot be completed.
    pub(crate) fn step<S: DaeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
    ) -> Result<Option<Status>, SolverError> {
        if self.st.cold_start() {
            self.st.k_used = 0;
            self.st.h_used = 0.0;
            self.st.psi[0] = self.st.h;
            self.st.phase = 0;
            self.st.ns = 0;
        }
        if let Some(p) = self
            .st
            .jacobian_point
            .as_ref()
            .filter(|_| self.needs_restore)
        {
            sys.setup_jacobian(p.t, &p.y, &p.yp, p.cj)?;
        }
        self.needs_restore = false;
        let fixed = self.opts.fixed_step.is_some();
        let mut ncf = 0usize;
        let mut nef = 0usize;
        let t_start = self.st.t;
        loop {
            let ck = set_coefficients(&mut self.st);
            self.st.t = t_start + self.st.h;
            let nls = self.nonlinear_solve(sys)?;
            let est = if nls == Nls::Converged {
                Some(test_error(&self.st, &mut self.w, ck))
            } else {
                None
            };
            let accepted = match est {
                Some(e) => e.passed || fixed,
                None => false,
            };
            if accepted {
                let est = est.expect("accepted implies an estimate");
                self.complete_step(est.err_k, est.err_km1, est.k_new);
                return Ok(None);
            }
            // Rejected: undo the step.
            restore(&mut self.st);
            self.st.t = t_start;
            let old_h = self.st.h;
            let rr;
            match est {
                None => {
                    self.st.stats.convergence_failures += 1;
                    ncf += 1;
                    self.st.force_setup = true;
                    if fixed || ncf >= self.opts.max_convergence_failures {
                        return Ok(Some(Status::ConvergenceFailures {
                            t: t_start,
                            h: old_h,
                            order: self.st.order,
                            residual_norm: self.w.last_res_norm,
                        }));
                    }
                    rr = after_convergence_failure();
                }
                Some(e) => {
                    self.st.stats.error_test_failures += 1;
                    nef += 1;
                    if nef >= self.opts.max_error_test_failures {
                        return Ok(Some(Status::ErrorTestFailures {
                            t: t_start,
                            h: old_h,
                            order: self.st.order,
                            error_norm: ck * e.enorm_k,
                        }));
                    }
                    let (k, r) = after_error_failure(&e, self.st.order, nef);
                    self.st.order = k;
                    rr = r;
                }
            }
            self.st.phase = 1;
            self.st.h *= rr;
            let h_floor = self
                .opts
                .h_min
                .max(100.0 * Real::EPSILON * t_start.abs().max(Real::MIN_POSITIVE));
            if self.st.h < h_floor {
                return Ok(Some(Status::StepSizeTooSmall {
                    t: t_start,
                    h: self.st.h,
                    order: self.st.order,
                    residual_norm: self.w.last_res_norm,
                }));
            }
            if self.st.cold_start() {
                self.st.psi[0] = self.st.h;
                for x in self.st.phi[1].iter_mut() {
                    *x *= rr;
                }
            }
        }
    }

    /// Bookkeeping after an accepted step and the choice of the next (h, order).
    fn complete_step(&mut self, err_k: Real, err_km1: Real, k_new: usize) {
        let st = &mut self.st;
        st.stats.steps += 1;
        let k = st.order;
        let k_diff = k as isize - st.k_used as isize;
        st.k_used = k;
        st.h_used = st.h;
        st.stats.order_histogram[k] += 1;
        st.stats.last_h = st.h;
        st.stats.last_order = k;
        let max_order = self.opts.max_order;
        let h_max = self.opts.h_max.unwrap_or(Real::INFINITY);
        if let Some(hf) = self.opts.fixed_step {
            // Fixed step: raise the order by one per step up to max_order, keep h.
            if st.order < max_order && st.steps_since_start() >= 1 {
                st.order += 1;
            }
            st.h = hf;
        } else {
            if k_new + 1 == k || k == max_order {
                st.phase = 1;
            }
            if st.phase == 0 {
                if st.steps_since_start() > 1 {
                    st.order += 1;
                    st.h = (2.0 * st.h).min(h_max);
                }
            } else {
                // Order decision: LOWER, MAINTAIN or RAISE.
                let mut err_new = err_k;
                let mut new_k = k;
                if k_new + 1 == k {
                    new_k = k - 1;
                    err_new = err_km1;
                } else if !(k == max_order || k + 1 >= st.ns || k_diff == 1) {
                    for i in 0..self.w.ee.len() {
                        self.w.tmp[i] = self.w.ee[i] - st.phi[k + 1][i];
                    }
                    let err_kp1 = wrms(&self.w.tmp, &self.w) / (k as Real + 2.0);
                    let terr_k = (k as Real + 1.0) * err_k;
                    let terr_kp1 = (k as Real + 2.0) * err_kp1;
                    if k == 1 {
                        if terr_kp1 < 0.5 * terr_k {
                            new_k = 2;
                            err_new = err_kp1;
                        }
                    } else {
                        let terr_km1 = k as Real * err_km1;
                        if terr_km1 <= terr_k.min(terr_kp1) {
                            new_k = k - 1;
                            err_new = err_km1;
                        } else if terr_kp1 < terr_k {
                            new_k = k + 1;
                            err_new = err_kp1;
                        }
                    }
                }
                st.order = new_k;
                let rr = (2.0 * err_new + 1e-4).powf(-1.0 / (new_k as Real + 1.0));
                if rr >= 2.0 {
                    st.h = (2.0 * st.h).min(h_max);
                } else if rr <= 1.0 {
                    st.h *= rr.clamp(0.5, 0.9);
                }
            }
        }
        // Save ee for a possible order increase, then update the differences.
        let ku = st.k_used;
        if ku < max_order {
            st.phi[ku + 1].copy_from_slice(&self.w.ee);
        }
        for i in 0..self.w.ee.len() {
            st.phi[ku][i] += self.w.ee[i];
        }
        for j in (0..ku).rev() {
            let (lo, hi) = st.phi.split_at_mut(j + 1);
            for (a, b) in lo[j].iter_mut().zip(&hi[0]) {
                *a += b;
            }
        }
        st.yp.copy_from_slice(&self.w.yp);
    }
}
