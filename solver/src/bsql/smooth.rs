//! A smooth unilateral law for compliant contact rows: the gap opens and closes through the
//! law itself, with no event.
//!
//! # Reference
//! A compliant row ([`super::compliance`]) carries the pressure of a linear spring on the
//! preloaded contact, $p_n = k_n\,x$ with the penetration beyond the opening level
//! $x = g_o − G_k u$, $g_o = c_k λ'_{open,k} = P_0/k_n$ (p_n = 0 at x = 0). Unilateral, the
//! pressure is $k_n \max(x, 0)$: with events ([`super::unilateral`]) the row switches at
//! x = 0. Here the max is replaced by a C² function of x that is exactly x for x ≥ ε and
//! exactly 0 for x ≤ −ε,
//! $$s_ε(x) = 2ε\,(τ^3 − τ^4/2),\quad τ = \frac{x + ε}{2ε} \in [0, 1],\qquad
//! s_ε'(x) = 3τ^2 − 2τ^3,\qquad s_ε''(x) = \frac{3τ(1 − τ)}{ε},$$
//! so $p_n = k_n s_ε(x)$ and the row reads
//! $$F_{λ,k} = S_k(G_k u) − c_k λ'_k,\qquad S_k(g) = g_o − s_ε(g_o − g)$$
//! (S_k(g) = g where the contact presses by at least k_n ε: the linear compliant row; and
//! S_k(g) = g_o, i.e. λ'_k = λ'_open, where the gap has opened by more than ε: the open
//! row). The law differs from the linear one only where the linear pressure is below
//! $p_ε = k_n ε$: it keeps $k_n s_ε(0) = 3 p_ε/16$ at x = 0 and lets go at x = −ε. A steady
//! state whose every gap presses by at least p_ε is the linear law's, bit for bit.
//!
//! The force is a gradient: $λ'_k = S_k(g)/c_k = ∂E_k/∂g$ with
//! $$E_k(g) = \frac{g_o g + Σ_ε(g_o − g) − g_o^2/2 − ε^2/10}{c_k},\quad
//! Σ_ε(x) = \int_{−ε}^{x} s_ε = 4ε^2(τ^4/4 − τ^5/10)\ (|x| < ε),\ \ x^2/2 + ε^2/10\ (x ≥ ε),$$
//! which is the linear row's $g^2/(2c_k)$ for x ≥ ε and the open row's
//! $λ'_{open} g − c_k λ'^2_{open}/2$ (less the constant ε²/(10 c_k)) for x ≤ −ε: the energy
//! balance closes with no impact term.
//!
//! In the iteration matrix the row's G_k is multiplied by $S_k' = s_ε'(x)$ at the point of
//! the set-up (its right-hand side too: see [`super::compliance`]).

use super::{BsqlSystem, FrictionForces};
use crate::{Real, SolverError};

/// s_ε(x), s_ε'(x) (see the module docs); ε > 0.
pub fn smooth_max(x: Real, eps: Real) -> (Real, Real) {
    if x >= eps {
        (x, 1.0)
    } else if x <= -eps {
        (0.0, 0.0)
    } else {
        let tau = (x + eps) / (2.0 * eps);
        let t2 = tau * tau;
        (
            2.0 * eps * (t2 * tau - 0.5 * t2 * t2),
            3.0 * t2 - 2.0 * t2 * tau,
        )
    }
}

/// Σ_ε(x) = ∫_{−ε}^{x} s_ε (see the module docs).
pub fn smooth_max_integral(x: Real, eps: Real) -> Real {
    if x >= eps {
        0.5 * x * x + 0.1 * eps * eps
    } else if x <= -eps {
        0.0
    } else {
        let tau = (x + eps) / (2.0 * eps);
        let t4 = tau * tau * tau * tau;
        4.0 * eps * eps * (0.25 * t4 - 0.1 * t4 * tau)
    }
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BsqlSystem<F> {
    /// Makes the compliant rows unilateral through the smooth law of the [module docs](self):
    /// `lambda_dot_open[k]` = P_0 A of gap k, `width[k]` = ε_k (a length: p_ε/k_n; 0 keeps row
    /// k linear). Needs the compliance set first ([`BsqlSystem::set_compliance`]); a rigid
    /// row (c_k = 0) must have width 0.
    pub fn set_smooth_unilateral(
        &mut self,
        lambda_dot_open: Vec<Real>,
        width: Vec<Real>,
    ) -> Result<(), SolverError> {
        let ng = self.ng;
        for (what, l) in [
            ("smooth-law opening force", lambda_dot_open.len()),
            ("smooth-law width", width.len()),
        ] {
            if l != ng {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: ng,
                    got: l,
                });
            }
        }
        for k in 0..ng {
            if !(width[k].is_finite() && width[k] >= 0.0 && lambda_dot_open[k].is_finite()) {
                return Err(SolverError::InvalidOption {
                    field: "smooth unilateral law",
                    value: format!(
                        "width {}, opening force {} (row {k})",
                        width[k], lambda_dot_open[k]
                    ),
                    reason: "the width must be finite and >= 0, the force finite",
                });
            }
            if width[k] > 0.0 && self.compliance_of(k) == 0.0 {
                return Err(SolverError::InvalidOption {
                    field: "smooth unilateral law",
                    value: format!("width {} on rigid row {k}", width[k]),
                    reason: "needs a compliant row (normal contact stiffness)",
                });
            }
        }
        self.factored = super::Factored::None;
        self.lambda_dot_open.copy_from_slice(&lambda_dot_open);
        if width.iter().all(|&w| w == 0.0) {
            self.smooth_width = Vec::new();
            self.smooth_slope = Vec::new();
        } else {
            self.smooth_slope = vec![1.0; ng];
            self.smooth_width = width;
        }
        Ok(())
    }

    /// ε of row k (0: no smooth law on it).
    #[inline]
    pub(crate) fn smooth_width_of(&self, k: usize) -> Real {
        self.smooth_width.get(k).copied().unwrap_or(0.0)
    }

    /// (S_k(g), S_k'(g)) of row k at g = G_k u (g, 1 without the smooth law).
    pub(crate) fn smooth_row(&self, k: usize, g: Real) -> (Real, Real) {
        let eps = self.smooth_width_of(k);
        if eps == 0.0 {
            return (g, 1.0);
        }
        let g_o = self.compliance_of(k) * self.lambda_dot_open[k];
        let (s, ds) = smooth_max(g_o - g, eps);
        (g_o - s, ds)
    }

    /// The stored energy of smooth row k at g = G_k u (see the module docs).
    pub(crate) fn smooth_row_energy(&self, k: usize, g: Real) -> Real {
        let (c, eps) = (self.compliance_of(k), self.smooth_width_of(k));
        let g_o = c * self.lambda_dot_open[k];
        (g_o * g + smooth_max_integral(g_o - g, eps) - 0.5 * g_o * g_o - 0.1 * eps * eps) / c
    }

    /// S_k' at the u of an iteration-matrix set-up, for every smooth row.
    pub(crate) fn update_smooth_slopes(&mut self, u: &[Real]) {
        for k in 0..self.smooth_width.len() {
            if self.smooth_width[k] > 0.0 {
                let g = self.g_row_dot(k, u);
                self.smooth_slope[k] = self.smooth_row(k, g).1;
            }
        }
    }

    /// S_k' of the last set-up (1 without the smooth law).
    #[inline]
    pub(crate) fn smooth_slope_of(&self, k: usize) -> Real {
        self.smooth_slope.get(k).copied().unwrap_or(1.0)
    }

    /// Whether any row has the smooth law.
    pub fn has_smooth_unilateral(&self) -> bool {
        !self.smooth_width.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// s_ε is C² with s = x for x ≥ ε, 0 for x ≤ −ε; s' and Σ are its derivative and
    /// integral (central differences).
    #[test]
    fn smooth_max_is_c2_and_its_derivative_and_integral_agree() {
        let eps = 0.3;
        let d = 1e-6;
        for i in 0..=200 {
            let x = -0.5 + i as Real * 0.005;
            let (s, ds) = smooth_max(x, eps);
            let fd = (smooth_max(x + d, eps).0 - smooth_max(x - d, eps).0) / (2.0 * d);
            assert!((ds - fd).abs() < 1e-8, "s' at {x}: {ds} vs {fd}");
            let fi =
                (smooth_max_integral(x + d, eps) - smooth_max_integral(x - d, eps)) / (2.0 * d);
            assert!((s - fi).abs() < 1e-8, "Σ' at {x}: {fi} vs {s}");
            if x >= eps {
                assert_eq!((s, ds), (x, 1.0));
            }
            if x <= -eps {
                assert_eq!((s, ds), (0.0, 0.0));
            }
        }
        // s'' continuous at ±ε (0 on both sides) and s(0) = 3ε/16.
        let dd = |x: Real| (smooth_max(x + d, eps).1 - smooth_max(x - d, eps).1) / (2.0 * d);
        assert!(dd(eps - 2.0 * d).abs() < 1e-4 && dd(-eps + 2.0 * d).abs() < 1e-4);
        assert!((smooth_max(0.0, eps).0 - 3.0 * eps / 16.0).abs() < 1e-15);
    }
}
