//! Restart at an event and root location on the interpolating polynomial (IDA's IDAReInit
//! and IDARcheck/IDARootfind, re-derived).
//!
//! # Reference
//! A root of g(t) = g(t, y(t), y'(t)) between the last two steps is located on the BDF
//! interpolant ([`Bdf::interpolate`]) by the Illinois variant of regula falsi: the secant
//! point of the bracket [t_lo, t_hi], halving the retained end's value when the same end is
//! kept twice, until the bracket is below `t_tol`. Only decreasing crossings (g > 0 → g ≤ 0)
//! are events (IDA's `rootdir = −1`); the bracket always keeps g(t_lo) > 0 ≥ g(t_hi). A
//! crossing that starts at zero (g(t_lo) ≤ 0 > g(t_hi): a function that sat at zero and left
//! it downwards) has its root at t_lo.

use super::{Bdf, BdfState};
use crate::{Real, SolverError};

/// Statistics of one root location.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RootFound {
    /// The located time (the right end of the final bracket: g(t) ≤ 0 there).
    pub t: Real,
    /// Evaluations of g.
    pub evals: usize,
}

impl Bdf {
    /// Restart the integration at (t, y, y') at order 1 with step `h` (an event: the
    /// solution or the system changed). The counters are kept; the difference arrays,
    /// step history and iteration matrix are dropped.
    pub fn reinit(&mut self, t: Real, y: &[Real], yp: &[Real], h: Real) -> Result<(), SolverError> {
        let n = self.st.n;
        if y.len() != n || yp.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "reinit state",
                expected: n,
                got: y.len().min(yp.len()),
            });
        }
        if !(h > 0.0 && h.is_finite() && t.is_finite()) {
            return Err(SolverError::InvalidOption {
                field: "reinit step",
                value: format!("t = {t}, h = {h}"),
                reason: "t must be finite and h finite and > 0",
            });
        }
        let stats = std::mem::take(&mut self.st.stats);
        let mut st = BdfState::new(t, y, yp, self.opts.max_order);
        // The start-up phase (order 1, doubling h) counts steps from here.
        st.start_step = stats.steps;
        st.stats = stats;
        st.collapse_count = self.st.collapse_count;
        let h = match self.opts.fixed_step {
            Some(hf) => hf,
            None => h.min(self.opts.h_max.unwrap_or(Real::INFINITY)),
        };
        st.h = h;
        st.psi[0] = h;
        for x in st.phi[1].iter_mut() {
            *x *= h;
        }
        st.h_pending = false;
        self.st = st;
        self.needs_restore = false;
        self.w.y_out.copy_from_slice(y);
        self.w.yp_out.copy_from_slice(yp);
        Ok(())
    }

    /// Locate a decreasing root of `g` on the last step, where g(t_lo) = `g_lo` > 0 and
    /// g(t_n) = `g_hi` ≤ 0 (t_lo = t_n − h_used); `t_tol` is the width at which to stop.
    /// With `g_lo` ≤ 0 (a crossing that starts at zero) the root is t_lo.
    pub fn locate_root<G>(
        &self,
        g_lo: Real,
        g_hi: Real,
        t_tol: Real,
        y: &mut [Real],
        yp: &mut [Real],
        mut g: G,
    ) -> Result<RootFound, SolverError>
    where
        G: FnMut(Real, &[Real], &[Real]) -> Result<Real, SolverError>,
    {
        let (mut a, mut b) = (self.st.t - self.st.h_used, self.st.t);
        let (mut ga, mut gb) = (g_lo, g_hi);
        let mut found = RootFound { t: b, evals: 0 };
        if ga <= 0.0 && gb <= 0.0 {
            found.t = a;
            return Ok(found);
        }
        if !(ga > 0.0 && gb <= 0.0) {
            return Ok(found);
        }
        let mut side = 0i8;
        while b - a > t_tol && found.evals < 100 {
            let mut tm = b - gb * (b - a) / (gb - ga);
            // Keep the trial point inside, away from the ends by a fraction of the bracket.
            let w = 0.1 * (b - a);
            tm = tm.clamp(a + w.min(0.5 * t_tol), b - w.min(0.5 * t_tol));
            self.interpolate(tm, y, yp)?;
            let gm = g(tm, y, yp)?;
            found.evals += 1;
            if gm > 0.0 {
                a = tm;
                ga = gm;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                b = tm;
                gb = gm;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        found.t = b;
        Ok(found)
    }
}
