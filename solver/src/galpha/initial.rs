//! Consistent initial accelerations q̈₀ and contact forces λ'₀.
//!
//! # Reference
//! Given v₀, u₀, solve eq. (16) with G q̈₀ = 0 [Paper eqs. (11), (16)]:
//! $$M \ddot q_0 + G^T f_0 = P(t_0) + F_f(f_0, v_0) − B v_0 − K u_0,\qquad G \ddot q_0 = 0,$$
//! by Newton's method with the matrix $\begin{bmatrix} M & G^T − ∂F_f/∂λ' \\ G & 0\end{bmatrix}$
//! (the step's iteration matrix at h = 0), re-formed every iteration.

use super::{Galpha, GalphaSystem};
use crate::bsql::FrictionForces;
use crate::{Real, SolverError};

/// Newton iterations allowed for the initial solve.
const MAX_ITERS: usize = 30;

fn inf_norm(x: &[Real], t: Real) -> Result<Real, SolverError> {
    let mut m: Real = 0.0;
    for (i, v) in x.iter().enumerate() {
        if !v.is_finite() {
            return Err(SolverError::NonFinite {
                what: "residual (generalized-α initial solve)",
                t,
                index: i,
                value: *v,
            });
        }
        m = m.max(v.abs());
    }
    Ok(m)
}

impl Galpha {
    /// Solve for `cur.qdd`, `cur.f` at `cur.t` (v, u, λ kept).
    pub(crate) fn initial_solve<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
    ) -> Result<(), SolverError> {
        let (n, ng) = (sys.n, sys.ng);
        let t = self.cur.t;
        let c = &mut self.cur;
        let res = &mut self.w.delta;
        // Force scale: the residual at q̈ = 0, f = 0.
        let (zq, zf) = (vec![0.0; n], vec![0.0; ng]);
        sys.residual(t, &zq, &zf, &c.v, &c.u, res)?;
        self.stats.residual_evals += 1;
        let tol = self.opts.initial_tol * inf_norm(res, t)?.max(1.0);
        let mut rn = Real::INFINITY;
        for it in 0..=MAX_ITERS {
            sys.residual(t, &c.qdd, &c.f, &c.v, &c.u, res)?;
            self.stats.residual_evals += 1;
            rn = inf_norm(res, t)?;
            if rn <= tol {
                return Ok(());
            }
            if it == MAX_ITERS {
                break;
            }
            sys.factor(t, &c.v, &c.f, 0.0, 0.0, false)?;
            self.stats.factorisations += 1;
            sys.solve(res)?;
            self.stats.newton_iterations += 1;
            for i in 0..n {
                c.qdd[i] -= res[i];
            }
            for k in 0..ng {
                c.f[k] -= res[n + k];
            }
        }
        Err(SolverError::NewtonFailed {
            what: "generalized-α initial accelerations",
            iterations: MAX_ITERS,
            residual: rn,
            tolerance: tol,
        })
    }
}
