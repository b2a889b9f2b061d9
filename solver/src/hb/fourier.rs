//! The real Fourier basis of a truncated periodic signal and its sampling (the "frequency–
//! time" halves of AFT).
//!
//! A signal y(θ) = Y_0 + Σ_{k=1}^{H} (Y_ck cos kθ + Y_sk sin kθ), θ = ωt, is stored as
//! [Y_0, Y_c1, Y_s1, …, Y_cH, Y_sH] (2H + 1 reals); its complex harmonic is Ŷ_k = Y_ck − i
//! Y_sk (y = Re Σ Ŷ_k e^{ikθ}), so that d/dt ↦ ikω on Ŷ_k. N equidistant samples θ_i = 2πi/N
//! with N > 2H give the exact coefficients of a signal with at most H harmonics by the
//! weights below (the trapezoidal rule, exact for trigonometric polynomials of degree < N).

use crate::Real;

/// The basis at N samples.
#[derive(Debug, Clone)]
pub(crate) struct Basis {
    /// Harmonics H.
    pub h: usize,
    /// Samples N.
    pub n: usize,
    /// E_i = [1, cos θ_i, sin θ_i, …] (row i at i·(2H + 1)).
    e: Vec<Real>,
    /// P_i = (1/N)[1, 2 cos θ_i, 2 sin θ_i, …]: Y_m = Σ_i P_i[m] y(θ_i).
    p: Vec<Real>,
}

impl Basis {
    /// The basis of H harmonics at N samples (N > 2H).
    pub(crate) fn new(h: usize, n: usize) -> Self {
        let m = 2 * h + 1;
        let mut e = vec![0.0; n * m];
        let mut p = vec![0.0; n * m];
        let inv = 1.0 / n as Real;
        for i in 0..n {
            let th = 2.0 * std::f64::consts::PI * i as Real / n as Real;
            e[i * m] = 1.0;
            p[i * m] = inv;
            for k in 1..=h {
                let (s, c) = (k as Real * th).sin_cos();
                e[i * m + 2 * k - 1] = c;
                e[i * m + 2 * k] = s;
                p[i * m + 2 * k - 1] = 2.0 * inv * c;
                p[i * m + 2 * k] = 2.0 * inv * s;
            }
        }
        Self { h, n, e, p }
    }

    /// Coefficients per signal, 2H + 1.
    pub(crate) fn m(&self) -> usize {
        2 * self.h + 1
    }

    /// E_i.
    pub(crate) fn e_row(&self, i: usize) -> &[Real] {
        let m = self.m();
        &self.e[i * m..(i + 1) * m]
    }

    /// P_i.
    pub(crate) fn p_row(&self, i: usize) -> &[Real] {
        let m = self.m();
        &self.p[i * m..(i + 1) * m]
    }

    /// y(θ_i) of the coefficients `c` (length 2H + 1).
    pub(crate) fn sample(&self, c: &[Real], i: usize) -> Real {
        self.e_row(i).iter().zip(c).map(|(a, b)| a * b).sum()
    }
}

/// y(θ) of the coefficients `c` (2H + 1) at any phase.
pub(crate) fn evaluate(c: &[Real], theta: Real) -> Real {
    let h = (c.len() - 1) / 2;
    let mut y = c[0];
    for k in 1..=h {
        let (s, co) = (k as Real * theta).sin_cos();
        y += c[2 * k - 1] * co + c[2 * k] * s;
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sampled coefficients of a trigonometric polynomial of degree H are exact.
    #[test]
    fn analysis_inverts_synthesis() {
        let h = 5;
        let b = Basis::new(h, 16);
        let c: Vec<Real> = (0..2 * h + 1)
            .map(|i| ((i * 7) % 5) as Real - 2.0)
            .collect();
        let mut back = vec![0.0; 2 * h + 1];
        for i in 0..b.n {
            let y = b.sample(&c, i);
            assert!(
                (y - evaluate(&c, 2.0 * std::f64::consts::PI * i as Real / 16.0)).abs() < 1e-12
            );
            for (m, w) in b.p_row(i).iter().enumerate() {
                back[m] += w * y;
            }
        }
        for (a, b) in back.iter().zip(&c) {
            assert!((a - b).abs() < 1e-12, "{back:?} vs {c:?}");
        }
    }
}
