//! Error weights, weighted RMS norm, the local error test, and failure recovery.
//!
//! # Reference
//! Weights $w_i = 1/(\mathrm{rtol}_i |y_i| + \mathrm{atol}_i)$ from y at the start of the step;
//! components with $\mathrm{atol}_i \ge 10^{20}$ get $w_i = 0$ and are excluded. The norm is
//! $\|x\| = \sqrt{\sum_{i∈A} (w_i x_i)^2 / |A|}$ over the set A of included components (IDA
//! divides by n; dividing by |A| keeps the test a true RMS over the controlled components).
//! The local error estimate at order k is $σ_k \|e\|$ with e the accumulated Newton
//! correction $y_n − y_n^{(0)}$; the step passes if $c_k \|e\| ≤ 1$.

use super::options::ATOL_EXCLUDED;
use super::state::BdfState;
use super::Work;
use crate::Real;

/// IDA's failure-recovery step factor.
const QUARTER: Real = 0.25;

/// Error weights from y.
pub(crate) fn set_weights(y: &[Real], w: &mut Work) {
    for i in 0..y.len() {
        w.ewt[i] = if w.atol[i] >= ATOL_EXCLUDED {
            0.0
        } else {
            1.0 / (w.rtol[i] * y[i].abs() + w.atol[i])
        };
    }
}

/// Weighted RMS norm over the included components (0 if none).
pub(crate) fn wrms(x: &[Real], w: &Work) -> Real {
    if w.n_active == 0 {
        return 0.0;
    }
    let mut s = 0.0;
    for (xi, wi) in x.iter().zip(&w.ewt) {
        let v = xi * wi;
        s += v * v;
    }
    (s / w.n_active as Real).sqrt()
}

/// Result of the error test: pass/fail, the order to use next (IDA's knew), the scaled
/// errors at orders k and k − 1, and the raw weighted norm at order k.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ErrorEstimate {
    pub passed: bool,
    pub k_new: usize,
    pub err_k: Real,
    pub err_km1: Real,
    pub enorm_k: Real,
}

/// IDA's error test, including the decision to lower the order. Uses `w.delta` and `w.tmp`.
pub(crate) fn test_error(st: &BdfState, w: &mut Work, ck: Real) -> ErrorEstimate {
    let k = st.order;
    let enorm_k = wrms(&w.ee, w);
    let err_k = st.sigma[k] * enorm_k;
    let terr_k = (k as Real + 1.0) * err_k;
    let mut k_new = k;
    let mut err_km1 = 0.0;
    if k > 1 {
        for i in 0..w.ee.len() {
            w.tmp[i] = st.phi[k][i] + w.ee[i];
        }
        let enorm_km1 = wrms(&w.tmp, w);
        err_km1 = st.sigma[k - 1] * enorm_km1;
        let terr_km1 = k as Real * err_km1;
        if k > 2 {
            for i in 0..w.ee.len() {
                w.tmp[i] += st.phi[k - 1][i];
            }
            let enorm_km2 = wrms(&w.tmp, w);
            let err_km2 = st.sigma[k - 2] * enorm_km2;
            let terr_km2 = (k as Real - 1.0) * err_km2;
            if terr_km1.max(terr_km2) <= terr_k {
                k_new = k - 1;
            }
        } else if terr_km1 <= 0.5 * terr_k {
            k_new = k - 1;
        }
    }
    ErrorEstimate {
        passed: ck * enorm_k <= 1.0,
        k_new,
        err_k,
        err_km1,
        enorm_k,
    }
}

/// New (order, step factor) after the `nef`-th error-test failure on this step (IDA):
/// first failure: order knew, factor 0.9·(2 err + 1e-4)^(−1/(k+1)) clipped to [0.25, 0.9];
/// second: order knew, factor 0.25; later: order 1, factor 0.25.
pub(crate) fn after_error_failure(est: &ErrorEstimate, order: usize, nef: usize) -> (usize, Real) {
    match nef {
        1 => {
            let err = if est.k_new == order {
                est.err_k
            } else {
                est.err_km1
            };
            let k = est.k_new;
            let rr = 0.9 * (2.0 * err + 1e-4).powf(-1.0 / (k as Real + 1.0));
            (k, rr.clamp(QUARTER, 0.9))
        }
        2 => (est.k_new, QUARTER),
        _ => (1, QUARTER),
    }
}

/// Step factor after a Newton convergence failure (IDA): 0.25.
pub(crate) fn after_convergence_failure() -> Real {
    QUARTER
}
