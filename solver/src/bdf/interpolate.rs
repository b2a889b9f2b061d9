//! Output between steps from the interpolating polynomial (IDA's IDAGetSolution).
//!
//! # Reference
//! With δ = t − t_n and the φ of the last accepted step of order k,
//! $y(t) = \sum_{j=0}^{k} c_j φ_j$, $y'(t) = \sum_{j=1}^{k} d_j φ_j$ where $c_0 = 1$,
//! $c_j = c_{j−1} γ_{j−1}$, $d_j = d_{j−1} γ_{j−1} + c_{j−1}/ψ_{j−1}$, $γ_0 = δ/ψ_0$,
//! $γ_j = (δ + ψ_{j−1})/ψ_j$. Valid on [t_n − h_used, t_n].

use super::Bdf;
use crate::{Real, SolverError};

impl Bdf {
    /// Interpolate y(t), y'(t) into `y`, `yp` for t in [t_n − h_used, t_n].
    pub fn interpolate(&self, t: Real, y: &mut [Real], yp: &mut [Real]) -> Result<(), SolverError> {
        let st = &self.st;
        let n = st.n;
        if y.len() != n || yp.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "interpolation output",
                expected: n,
                got: y.len().min(yp.len()),
            });
        }
        if st.steps_since_start() == 0 {
            if t == st.t {
                y.copy_from_slice(&st.phi[0]);
                yp.copy_from_slice(&st.yp);
                return Ok(());
            }
            return Err(SolverError::BadOutputTime {
                tout: t,
                t_min: st.t,
                t_max: st.t,
            });
        }
        let t_min = st.t - st.h_used;
        let slack = 100.0 * Real::EPSILON * (st.t.abs() + st.h_used.abs());
        if t < t_min - slack || t > st.t + slack {
            return Err(SolverError::BadOutputTime {
                tout: t,
                t_min,
                t_max: st.t,
            });
        }
        let k = st.k_used.max(1);
        let delt = t - st.t;
        let mut c = 1.0;
        let mut d = 0.0;
        let mut gam = delt / st.psi[0];
        y.copy_from_slice(&st.phi[0]);
        yp.fill(0.0);
        for j in 1..=k {
            d = d * gam + c / st.psi[j - 1];
            c *= gam;
            gam = (delt + st.psi[j - 1]) / st.psi[j];
            for i in 0..n {
                y[i] += c * st.phi[j][i];
                yp[i] += d * st.phi[j][i];
            }
        }
        Ok(())
    }

    /// Interpolate into the output buffers returned by `y()`/`yp()`.
    pub(crate) fn interpolate_into_output(&mut self, t: Real) -> Result<(), SolverError> {
        let mut y = std::mem::take(&mut self.w.y_out);
        let mut yp = std::mem::take(&mut self.w.yp_out);
        let r = self.interpolate(t, &mut y, &mut yp);
        self.w.y_out = y;
        self.w.yp_out = yp;
        r
    }
}
