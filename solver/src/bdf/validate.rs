//! Checks of a saved [`BdfState`] before it is restored: every length, index and number the
//! step code relies on, so that a hand-edited or damaged restart is an error naming the field,
//! never an index out of bounds or a NaN step.

use super::state::BdfState;
use crate::{Real, SolverError};

fn bad(field: impl Into<String>, message: String) -> SolverError {
    SolverError::InvalidState {
        field: field.into(),
        message,
    }
}

fn finite(field: &str, v: Real) -> Result<(), SolverError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(bad(field, format!("{v} must be finite")))
    }
}

fn finite_all(field: &str, v: &[Real]) -> Result<(), SolverError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(bad(
            format!("{field}[{i}]"),
            format!("{} must be finite", v[i]),
        )),
        None => Ok(()),
    }
}

fn length(field: &str, got: usize, want: usize, why: &str) -> Result<(), SolverError> {
    if got == want {
        Ok(())
    } else {
        Err(bad(
            field,
            format!("has {got} entries, expected {want} ({why})"),
        ))
    }
}

impl BdfState {
    /// Checks the state for an integrator of orders up to `max_order` (see the module).
    pub fn validate(&self, max_order: usize) -> Result<(), SolverError> {
        let (n, m) = (self.n, max_order.saturating_add(2));
        let arrays = "max_order + 2";
        length("phi", self.phi.len(), m, arrays)?;
        for (i, p) in self.phi.iter().enumerate() {
            length(&format!("phi[{i}]"), p.len(), n, "n")?;
            finite_all(&format!("phi[{i}]"), p)?;
        }
        length("yp", self.yp.len(), n, "n")?;
        finite_all("yp", &self.yp)?;
        for (name, v) in [
            ("psi", &self.psi),
            ("alpha", &self.alpha),
            ("beta", &self.beta),
            ("sigma", &self.sigma),
            ("gamma", &self.gamma),
        ] {
            length(name, v.len(), m, arrays)?;
            finite_all(name, v)?;
        }
        for (name, v) in [
            ("t", self.t),
            ("h_used", self.h_used),
            ("cj", self.cj),
            ("cj_old", self.cj_old),
            ("cj_last", self.cj_last),
            ("ss", self.ss),
        ] {
            finite(name, v)?;
        }
        if self.start_step > self.stats.steps {
            return Err(bad(
                "start_step",
                format!(
                    "{} must not exceed stats.steps = {} (the steps at the last restart)",
                    self.start_step, self.stats.steps
                ),
            ));
        }
        if !(self.h.is_finite() && (self.h > 0.0 || (self.h_pending && self.h == 0.0))) {
            return Err(bad(
                "h",
                format!(
                    "{} must be finite and > 0 (0 only before the first step, h_pending)",
                    self.h
                ),
            ));
        }
        if self.h_used < 0.0 {
            return Err(bad("h_used", format!("{} must be >= 0", self.h_used)));
        }
        if !(1..=max_order).contains(&self.order) {
            return Err(bad(
                "order",
                format!("{} is not in 1..={max_order} (max_order)", self.order),
            ));
        }
        if self.k_used > max_order {
            return Err(bad(
                "k_used",
                format!("{} is above max_order {max_order}", self.k_used),
            ));
        }
        if self.ns > self.k_used.saturating_add(2) {
            return Err(bad(
                "ns",
                format!("{} is above k_used + 2 = {}", self.ns, self.k_used + 2),
            ));
        }
        if self.phase > 1 {
            return Err(bad("phase", format!("{} is not 0 or 1", self.phase)));
        }
        // After a step ψ holds the last steps summed (ψ_0 = h_used, the step just taken),
        // strictly increasing: the coefficients divide by them (fuzzing: ψ_0 = 1e-320 gave NaN
        // friction forces). Before any step the integrator sets ψ_0 = h itself.
        if self.h_used > 0.0 && (self.psi[0] - self.h_used).abs() > 1e-12 * self.h_used {
            return Err(bad(
                "psi",
                format!(
                    "psi[0] = {} must equal the last step h_used = {}",
                    self.psi[0], self.h_used
                ),
            ));
        }
        for i in 1..=self.k_used.min(self.psi.len() - 1) {
            if self.psi[i] <= self.psi[i - 1] {
                return Err(bad(
                    "psi",
                    format!(
                        "psi[{i}] = {} must exceed psi[{}] = {} (sums of the last steps)",
                        self.psi[i],
                        i - 1,
                        self.psi[i - 1]
                    ),
                ));
            }
        }
        if let Some(p) = &self.jacobian_point {
            length("jacobian_point.y", p.y.len(), n, "n")?;
            length("jacobian_point.yp", p.yp.len(), n, "n")?;
            finite("jacobian_point.t", p.t)?;
            finite("jacobian_point.cj", p.cj)?;
            // The matrix was formed at cj_old = jacobian_point.cj (newton.rs sets both at once):
            // any other value re-forms a matrix the run never used (found by fuzzing: 1e308).
            if p.cj <= 0.0 || p.cj != self.cj_old {
                return Err(bad(
                    "jacobian_point.cj",
                    format!(
                        "{} must be positive and equal cj_old = {} (the iteration matrix's cj)",
                        p.cj, self.cj_old
                    ),
                ));
            }
            finite_all("jacobian_point.y", &p.y)?;
            finite_all("jacobian_point.yp", &p.yp)?;
        }
        let s = &self.stats;
        length(
            "stats.order_histogram",
            s.order_histogram.len(),
            max_order.saturating_add(1),
            "max_order + 1",
        )?;
        if s.last_order > max_order {
            return Err(bad(
                "stats.last_order",
                format!("{} is above max_order {max_order}", s.last_order),
            ));
        }
        finite("stats.last_h", s.last_h)?;
        finite("stats.cpu_s", s.cpu_s)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bdf::{Bdf, BdfOptions};

    fn err(st: BdfState) -> String {
        Bdf::from_state(BdfOptions::default(), st)
            .unwrap_err()
            .to_string()
    }

    /// The two states that panicked in the step code are errors naming the field.
    #[test]
    fn states_that_panicked_are_errors_naming_the_field() {
        let fresh = BdfState::new(0.0, &[1.0, 2.0], &[0.0, 0.5], 2);
        assert!(Bdf::from_state(BdfOptions::default(), fresh.clone()).is_ok());
        let mut st = fresh.clone();
        st.order = 3;
        assert!(err(st).contains("`order`: 3 is not in 1..=2"));
        let mut st = fresh.clone();
        st.stats.order_histogram.clear();
        assert!(err(st).contains("`stats.order_histogram`: has 0 entries, expected 3"));
        let mut st = fresh.clone();
        st.h_pending = false;
        assert!(err(st).contains("`h`: 0 must be finite and > 0"));
        let mut st = fresh.clone();
        st.yp.pop();
        assert!(err(st).contains("`yp`: has 1 entries, expected 2"));
        let mut st = fresh.clone();
        st.phi[2][1] = f64::NAN;
        assert!(err(st).contains("`phi[2][1]`: NaN must be finite"));
        // A restart point after the steps taken (a restart file from a run with events).
        let mut st = fresh;
        st.start_step = 5;
        assert!(err(st).contains("`start_step`: 5 must not exceed stats.steps = 0"));
    }
}
