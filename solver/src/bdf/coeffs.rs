//! Step coefficients of the fixed-leading-coefficient BDF in φ form, the predictor, and the
//! undo of a rejected step.
//!
//! # Reference
//! With ψ_i(n) = t_n − t_{n−i−1} the modified divided differences φ_i(n) are scaled so that
//! the predictor is $y^{(0)}_{n+1} = \sum_{i=0}^{k} φ_i^*(n)$,
//! $y'^{(0)}_{n+1} = \sum_{i=1}^{k} γ_i(n+1) φ_i^*(n)$ with $φ_i^* = β_i φ_i$, and the
//! corrector is $y'_{n+1} = y'^{(0)}_{n+1} + c_j (y_{n+1} − y^{(0)}_{n+1})$ with
//! $c_j = −α_s/h$, $α_s = −\sum_{j=1}^{k} 1/j$ (Brenan, Campbell & Petzold §5.2; IDA).
//! This is the "integration operator α" of [Paper eq. (17)].

use super::state::BdfState;
use super::Work;

/// Compute α, β, σ, γ, ψ and cj for the step about to be taken with (h, order); return the
/// error constant ck. Also scales φ_i by β_i for i ≥ ns (IDA's φ*).
pub(crate) fn set_coefficients(st: &mut BdfState) -> f64 {
    let k = st.order;
    let h = st.h;
    if h != st.h_used || k != st.k_used {
        st.ns = 0;
    }
    st.ns = (st.ns + 1).min(st.k_used + 2);
    if k + 1 >= st.ns {
        st.beta[0] = 1.0;
        st.alpha[0] = 1.0;
        st.gamma[0] = 0.0;
        st.sigma[0] = 1.0;
        let mut temp1 = h;
        for i in 1..=k {
            let temp2 = st.psi[i - 1];
            st.psi[i - 1] = temp1;
            st.beta[i] = st.beta[i - 1] * st.psi[i - 1] / temp2;
            temp1 = temp2 + h;
            st.alpha[i] = h / temp1;
            st.sigma[i] = i as f64 * st.sigma[i - 1] * st.alpha[i];
            st.gamma[i] = st.gamma[i - 1] + st.alpha[i - 1] / h;
        }
        st.psi[k] = temp1;
    }
    let mut alphas = 0.0;
    let mut alpha0 = 0.0;
    for i in 0..k {
        alphas -= 1.0 / (i as f64 + 1.0);
        alpha0 -= st.alpha[i];
    }
    st.cj_last = st.cj;
    st.cj = -alphas / h;
    let ck = (st.alpha[k] + alphas - alpha0).abs().max(st.alpha[k]);
    if st.ns <= k {
        for i in st.ns..=k {
            let b = st.beta[i];
            for x in st.phi[i].iter_mut() {
                *x *= b;
            }
        }
    }
    ck
}

/// Predictor: yy = Σ_{i≤k} φ_i, yp = Σ_{1≤i≤k} γ_i φ_i; clears the accumulated correction ee.
pub(crate) fn predict(st: &BdfState, w: &mut Work) {
    let k = st.order;
    w.yy.copy_from_slice(&st.phi[0]);
    w.yp.fill(0.0);
    for j in 1..=k {
        let g = st.gamma[j];
        for ((y, yp), p) in w.yy.iter_mut().zip(w.yp.iter_mut()).zip(&st.phi[j]) {
            *y += p;
            *yp += g * p;
        }
    }
    w.ee.fill(0.0);
}

/// Undo `set_coefficients` after a rejected step (IDA's restore): ψ and φ* back to φ.
pub(crate) fn restore(st: &mut BdfState) {
    let k = st.order;
    for j in 1..=k {
        st.psi[j - 1] = st.psi[j] - st.h;
    }
    if st.ns <= k {
        for j in st.ns..=k {
            let b = 1.0 / st.beta[j];
            for x in st.phi[j].iter_mut() {
                *x *= b;
            }
        }
    }
}
