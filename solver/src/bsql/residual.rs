//! The BSQL residual, paper eq. (16), and the load history P(t).

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use serde::{Deserialize, Serialize};

use super::{BsqlSystem, FrictionForces};
use crate::{Real, SolverError};

/// Loads P(t) = p_pre + r(t)·p_brake with r(t) = min(t/t_load, 1) for t ≥ 0 (0 before), or a
/// step r = 1 for t ≥ 0 when `step` is set or `t_load` = 0 (BSQL's PMAX/TLOAD).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LoadHistory {
    /// Constant preload vector, length n (default: empty = zero).
    pub p_pre: Vec<Real>,
    /// Brake load vector scaled by the ramp, length n (default: empty = zero).
    pub p_brake: Vec<Real>,
    /// Ramp time TLOAD (default: 0 = step).
    pub t_load: Real,
    /// Apply p_brake as a step at t = 0 (default: false).
    pub step: bool,
}

impl Default for LoadHistory {
    fn default() -> Self {
        Self {
            p_pre: Vec::new(),
            p_brake: Vec::new(),
            t_load: 0.0,
            step: false,
        }
    }
}

impl LoadHistory {
    /// Check lengths (0 or n) and the ramp time.
    pub fn validate(&self, n: usize) -> Result<(), SolverError> {
        for (what, v) in [("p_pre", &self.p_pre), ("p_brake", &self.p_brake)] {
            if !v.is_empty() && v.len() != n {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: n,
                    got: v.len(),
                });
            }
        }
        if !(self.t_load >= 0.0 && self.t_load.is_finite()) {
            return Err(SolverError::InvalidOption {
                field: "t_load",
                value: self.t_load.to_string(),
                reason: "must be finite and >= 0",
            });
        }
        Ok(())
    }

    /// Ramp factor r(t).
    pub fn ramp(&self, t: Real) -> Real {
        if t < 0.0 {
            0.0
        } else if self.step || self.t_load == 0.0 {
            1.0
        } else {
            (t / self.t_load).min(1.0)
        }
    }

    /// P(t) · v.
    pub fn dot(&self, t: Real, v: &[Real]) -> Real {
        let pre: Real = self.p_pre.iter().zip(v).map(|(p, x)| p * x).sum();
        let brake: Real = self.p_brake.iter().zip(v).map(|(p, x)| p * x).sum();
        pre + self.ramp(t) * brake
    }

    /// f ← f + α·P(t).
    pub fn add_to(&self, t: Real, alpha: Real, f: &mut [Real]) {
        for (fi, p) in f.iter_mut().zip(&self.p_pre) {
            *fi += alpha * p;
        }
        let r = alpha * self.ramp(t);
        for (fi, p) in f.iter_mut().zip(&self.p_brake) {
            *fi += r * p;
        }
    }
}

/// y ← β·y + α·A x (β = 0 for `Accum::Replace`, 1 for `Accum::Add`).
pub(crate) fn matvec(a: MatRef<'_, Real>, x: &[Real], y: &mut [Real], accum: Accum, alpha: Real) {
    let xr = MatRef::from_column_major_slice(x, x.len(), 1);
    let n = y.len();
    let yr = MatMut::from_column_major_slice_mut(y, n, 1);
    matmul(yr, accum, a, xr, alpha, Par::Seq);
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BsqlSystem<F> {
    /// F(t, y, y') of eq. (16).
    ///
    /// # Reference
    /// $$F_v = M v' + B v + K u + G^T λ' − P(t) − F_f(λ', v),\quad F_λ = G v',\quad F_u = u' − v$$
    /// [Paper eq. (16)] with y = {v, λ, u} (λ the contact impulse, see DESIGN.md). The row
    /// of an open constraint k (see [`super::unilateral`]) is $F_{λ,k} = λ'_k − λ'_{open,k}$,
    /// that of a compliant one $F_{λ,k} = G_k u − c_k λ'_k$ (see [`super::compliance`]).
    pub(crate) fn eval_residual(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        res: &mut [Real],
    ) -> Result<(), SolverError> {
        let (n, ng) = (self.n, self.ng);
        let len = 2 * n + ng;
        for (what, l) in [("y", y.len()), ("y'", yp.len()), ("residual", res.len())] {
            if l != len {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: len,
                    got: l,
                });
            }
        }
        self.stats.residual_evals += 1;
        let (v, _lam, u) = (&y[..n], &y[n..n + ng], &y[n + ng..]);
        let (vp, lamp, up) = (&yp[..n], &yp[n..n + ng], &yp[n + ng..]);
        let (rv, rest) = res.split_at_mut(n);
        let (rl, ru) = rest.split_at_mut(ng);
        // F_v  [Paper eq. (16)] (M v' + B v + K u in one pass over their union pattern)
        self.mbk.apply3(vp, v, u, rv);
        self.gt_rows.apply(0, lamp, rv, true, 1.0);
        self.load.add_to(t, -1.0, rv);
        self.f_n.fill(0.0);
        self.friction.add_forces(t, v, lamp, &mut self.f_n)?;
        for (i, (r, f)) in rv.iter_mut().zip(&self.f_n).enumerate() {
            if !f.is_finite() {
                return Err(SolverError::NonFinite {
                    what: "friction force",
                    t,
                    index: i,
                    value: *f,
                });
            }
            *r -= f;
        }
        // F_λ = G v'  [Paper eq. (11)]; an open constraint's row is λ' − λ'_open.
        self.g_rows.apply(0, vp, rl, false, 1.0);
        for k in 0..ng {
            if self.open[k] {
                rl[k] = lamp[k] - self.lambda_dot_open[k];
            }
        }
        // A compliant row: F_λ = G u − c λ' (see [`super::compliance`]).
        self.compliant_residual(u, lamp, rl);
        // F_u = u' − v  [Paper eq. (10)]
        for i in 0..n {
            ru[i] = up[i] - v[i];
        }
        Ok(())
    }
}
