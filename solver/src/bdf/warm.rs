//! Restart at order 2 from a Taylor start: after an event (a switch of the system, a jump of
//! the state) the BDF continues at order 2 instead of climbing up from order 1.
//!
//! # Reference
//! The variable-step BDF in φ form (Brenan, Campbell & Petzold §5.2; IDA) needs, for order k,
//! the modified divided differences φ_0..φ_k of the last k + 1 solution values. After an
//! event the past values belong to another system (or jump), so [`Bdf::reinit`] starts at
//! order 1 from (y, y') alone. Here a past is made up that the new system's solution does
//! have: the quadratic Taylor polynomial of the solution after the event,
//! $$\tilde y(s) = y + (s − t) y' + \tfrac12 (s − t)^2 y'',$$
//! sampled at t − h and t − 2h, with y'' of the new system (see [`second_derivative`]). With
//! ψ_0 = h, ψ_1 = 2h the divided differences of these three values are
//! $$φ_0 = y,\qquad φ_1 = y − \tilde y(t − h) = h y' − \tfrac12 h^2 y'',\qquad
//! φ_2 = ψ_0 ψ_1\,[\tilde y_n, \tilde y_{n−1}, \tilde y_{n−2}] = h^2 y'',$$
//! and the BDF2 predictor from them is the Taylor polynomial at t + h. The made-up past
//! differs from the true one by O(h³ y'''), the local error of BDF2 itself, so the first
//! steps are of order 2 (their error estimate is BDF2's). A rejected first step keeps this
//! past and shrinks h as after any step ([`super::step`]).
//!
//! y'' of the DAE F(t, y, y') = 0 with ∂F/∂y' nonsingular (index 0, as the BSQL system):
//! differentiating along the solution, $F_t + F_y y' + F_{y'} y'' = 0$, so
//! $$y'' = −(∂F/∂y')^{-1}\, \frac{F(t+δ, y+δy', y') − F(t−δ, y−δy', y')}{2δ}$$
//! (a central difference of F along (1, y') at fixed y', error O(δ²)).

use super::{Bdf, BdfState, DaeSystem};
use crate::{Real, SolverError};

/// y'' at a consistent (t, y, y') of an index-0 system, into `ypp` (see the module docs);
/// `delta` is the difference step in t. Returns false (and leaves `ypp`) when the system does
/// not provide ∂F/∂y' ([`DaeSystem::setup_derivative_jacobian`]). The system's factorisation
/// is left holding ∂F/∂y'.
pub fn second_derivative<S: DaeSystem + ?Sized>(
    sys: &mut S,
    t: Real,
    y: &[Real],
    yp: &[Real],
    delta: Real,
    ypp: &mut [Real],
) -> Result<bool, SolverError> {
    let n = sys.len();
    for (what, l) in [("y", y.len()), ("y'", yp.len()), ("y''", ypp.len())] {
        if l != n {
            return Err(SolverError::DimensionMismatch {
                what,
                expected: n,
                got: l,
            });
        }
    }
    if !(delta > 0.0 && delta.is_finite()) {
        return Err(SolverError::InvalidOption {
            field: "second-derivative step",
            value: delta.to_string(),
            reason: "must be finite and > 0",
        });
    }
    let mut ys: Vec<Real> = y.iter().zip(yp).map(|(a, b)| a + delta * b).collect();
    let mut r_plus = vec![0.0; n];
    sys.residual(t + delta, &ys, yp, &mut r_plus)?;
    for i in 0..n {
        ys[i] = y[i] - delta * yp[i];
    }
    sys.residual(t - delta, &ys, yp, ypp)?;
    for i in 0..n {
        ypp[i] = (r_plus[i] - ypp[i]) / (2.0 * delta);
    }
    if !sys.setup_derivative_jacobian(t, y, yp)? {
        return Ok(false);
    }
    sys.solve_jacobian(ypp)?;
    for (i, x) in ypp.iter_mut().enumerate() {
        *x = -*x;
        if !x.is_finite() {
            return Err(SolverError::NonFinite {
                what: "second derivative y''",
                t,
                index: i,
                value: *x,
            });
        }
    }
    Ok(true)
}

impl Bdf {
    /// Restart the integration at (t, y, y') at order 2 with step `h`, from the Taylor past
    /// of (y, y', y'') (see the module docs). With `max_order` 1 (or a fixed step) this is
    /// [`Bdf::reinit`]. The counters are kept; the iteration matrix is formed anew.
    pub fn reinit_taylor(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        ypp: &[Real],
        h: Real,
    ) -> Result<(), SolverError> {
        if self.opts.max_order < 2 || self.opts.fixed_step.is_some() {
            return self.reinit(t, y, yp, h);
        }
        let n = self.st.n;
        if y.len() != n || yp.len() != n || ypp.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "reinit state",
                expected: n,
                got: y.len().min(yp.len()).min(ypp.len()),
            });
        }
        if !(h > 0.0 && h.is_finite() && t.is_finite()) {
            return Err(SolverError::InvalidOption {
                field: "reinit step",
                value: format!("t = {t}, h = {h}"),
                reason: "t must be finite and h finite and > 0",
            });
        }
        if let Some(i) = ypp.iter().position(|x| !x.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "reinit y''",
                t,
                index: i,
                value: ypp[i],
            });
        }
        let h = h.min(self.opts.h_max.unwrap_or(Real::INFINITY));
        let stats = std::mem::take(&mut self.st.stats);
        let mut st = BdfState::new(t, y, yp, self.opts.max_order);
        st.start_step = stats.steps;
        st.stats = stats;
        st.collapse_count = self.st.collapse_count;
        st.warm = true;
        st.h = h;
        st.h_used = h;
        st.k_used = 2;
        st.order = 2;
        st.phase = 1;
        st.ns = 0;
        st.psi[0] = h;
        st.psi[1] = 2.0 * h;
        for i in 0..n {
            st.phi[1][i] = h * yp[i] - 0.5 * h * h * ypp[i];
            st.phi[2][i] = h * h * ypp[i];
        }
        st.h_pending = false;
        self.st = st;
        self.needs_restore = false;
        self.w.y_out.copy_from_slice(y);
        self.w.yp_out.copy_from_slice(yp);
        Ok(())
    }
}
