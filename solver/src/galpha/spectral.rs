//! Linear stability theory of the generalized-α scheme: amplification matrix, spectral
//! radius and algorithmic damping on q̈ + 2ζω q̇ + ω² q = 0.
//!
//! # Reference
//! Chung & Hulbert (1993), §3; written here for the Arnold–Brüls form of [`super`], whose
//! linear amplification matrix has the same characteristic polynomial. With Ω = ωh and the
//! state x_n = (q_n, h v_n, h² a_n), eliminating h² q̈ = −Ω² q − 2ζΩ (h v) gives
//! L x_{n+1} = R x_n with
//! $$L = \begin{bmatrix} (1−α_f)Ω^2 & 2ζΩ(1−α_f) & 1−α_m \\ 0 & 1 & −γ \\ 1 & 0 & −β\end{bmatrix},\quad
//! R = \begin{bmatrix} −α_fΩ^2 & −2ζΩα_f & −α_m \\ 0 & 1 & 1−γ \\ 1 & 1 & \tfrac12−β\end{bmatrix},$$
//! and A = L⁻¹R. The principal roots ξ, ξ̄ of det(A − ξI) = 0 give s = ln ξ / h, the
//! algorithmic damping ratio ζ̄ = −Re s/|s| and the period error; the third (spurious)
//! root has |ξ₃| → |α_m/(1−α_m)| as Ω → 0, and max|ξ| → ρ∞ as Ω → ∞.
//!
//! Leading order for ζ = 0 (checked against these roots to 4 digits for ρ∞ ∈ [0.5, 1]):
//! $$\bar ζ ≈ \tfrac12\Big(\frac{1−ρ_∞}{1+ρ_∞}\Big)^3 Ω^3 .$$

use num_complex::Complex64;
use serde::Serialize;

use super::GalphaCoeffs;
use crate::Real;

/// Amplification matrix A (row-major) on (q, h v, h² a) at Ω = ωh and physical damping ζ.
pub fn amplification_matrix(co: &GalphaCoeffs, omega_h: Real, zeta: Real) -> [[Real; 3]; 3] {
    let (am, af, g, b) = (co.alpha_m, co.alpha_f, co.gamma, co.beta);
    let w2 = omega_h * omega_h;
    let d = 2.0 * zeta * omega_h;
    let l = [
        [(1.0 - af) * w2, (1.0 - af) * d, 1.0 - am],
        [0.0, 1.0, -g],
        [1.0, 0.0, -b],
    ];
    let r = [
        [-af * w2, -af * d, -am],
        [0.0, 1.0, 1.0 - g],
        [1.0, 1.0, 0.5 - b],
    ];
    // A = L⁻¹ R by Cramer's rule (L is 3 × 3 and nonsingular for Ω ≥ 0).
    let det3 = |m: &[[Real; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let dl = det3(&l);
    let mut a = [[0.0; 3]; 3];
    for col in 0..3 {
        for row in 0..3 {
            let mut m = l;
            for k in 0..3 {
                m[k][row] = r[k][col];
            }
            a[row][col] = det3(&m) / dl;
        }
    }
    a
}

/// The three eigenvalues of a real 3 × 3 matrix (Durand–Kerner on its characteristic
/// polynomial ξ³ − tr ξ² + m₂ ξ − det).
pub fn eigenvalues3(a: &[[Real; 3]; 3]) -> [Complex64; 3] {
    let tr = a[0][0] + a[1][1] + a[2][2];
    let m2 = a[0][0] * a[1][1] - a[0][1] * a[1][0] + a[0][0] * a[2][2] - a[0][2] * a[2][0]
        + a[1][1] * a[2][2]
        - a[1][2] * a[2][1];
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    let p = |x: Complex64| ((x - tr) * x + m2) * x - det;
    let seed = Complex64::new(0.4, 0.9);
    let mut z = [Complex64::new(1.0, 0.0), seed, seed * seed];
    for _ in 0..500 {
        let mut change: Real = 0.0;
        for i in 0..3 {
            let mut den = Complex64::new(1.0, 0.0);
            for j in 0..3 {
                if j != i {
                    den *= z[i] - z[j];
                }
            }
            let step = p(z[i]) / den;
            z[i] -= step;
            change = change.max(step.norm());
        }
        if change < 1e-15 {
            break;
        }
    }
    // Polish each root with Newton on p.
    for zi in z.iter_mut() {
        for _ in 0..3 {
            let dp = (3.0 * *zi - 2.0 * tr) * *zi + m2;
            if dp.norm() > 0.0 {
                *zi -= p(*zi) / dp;
            }
        }
    }
    z
}

/// Largest |ξ| of the amplification matrix at Ω = ωh (ζ = 0).
pub fn spectral_radius(co: &GalphaCoeffs, omega_h: Real) -> Real {
    eigenvalues3(&amplification_matrix(co, omega_h, 0.0))
        .iter()
        .fold(0.0, |m, z| m.max(z.norm()))
}

/// The principal root: the eigenvalue closest to the exact e^{(−ζ + i√(1−ζ²))Ω} (ζ < 1).
pub fn principal_root(co: &GalphaCoeffs, omega_h: Real, zeta: Real) -> Complex64 {
    let exact = Complex64::new(-zeta, (1.0 - zeta * zeta).max(0.0).sqrt()) * omega_h;
    let target = exact.exp();
    let ev = eigenvalues3(&amplification_matrix(co, omega_h, zeta));
    let mut best = ev[0];
    for z in ev {
        if (z - target).norm() < (best - target).norm() {
            best = z;
        }
    }
    best
}

/// Algorithmic damping and period error of the undamped oscillator at one Ω = ωh.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AlgorithmicDamping {
    /// Ω = ωh.
    pub omega_h: Real,
    /// Damping ratio ζ̄ = −Re s/|s| with s = ln ξ (principal root).
    pub zeta: Real,
    /// Relative period elongation Ω/Im(ln ξ) − 1.
    pub period_error: Real,
    /// Spectral radius at this Ω.
    pub spectral_radius: Real,
}

/// Algorithmic damping of the scheme at Ω = ωh (undamped oscillator).
pub fn algorithmic_damping(co: &GalphaCoeffs, omega_h: Real) -> AlgorithmicDamping {
    let s = principal_root(co, omega_h, 0.0).ln();
    AlgorithmicDamping {
        omega_h,
        zeta: -s.re / s.norm(),
        period_error: omega_h / s.im - 1.0,
        spectral_radius: spectral_radius(co, omega_h),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_of_a_known_matrix() {
        // Companion-like matrix with roots 0.5, 0.6 ± 0.7i: ξ³ − 1.7ξ² + 1.45ξ − 0.425.
        let a = [[1.7, -1.45, 0.425], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mut ev = eigenvalues3(&a);
        ev.sort_by(|x, y| x.im.partial_cmp(&y.im).unwrap());
        let want = [
            Complex64::new(0.6, -0.7),
            Complex64::new(0.5, 0.0),
            Complex64::new(0.6, 0.7),
        ];
        for (z, w) in ev.iter().zip(want) {
            assert!((z - w).norm() < 1e-12, "{ev:?}");
        }
    }
}
