//! The arctangent regularisation of eq. (5).

use crate::Real;

/// atan(10), the value of the arctangent at the end of the transition zone.
const ATAN_10: Real = 1.471_127_674_303_734_7;

/// Regularisation of the friction direction near zero sliding speed: returns
/// `(φ(s), φ'(s)/s)` where the pad force is `f_p = F_t · φ(|V_t|) · V_t` and
///
/// ```text
/// φ(s) = r(s)/s,   r(s) = atan(s/VTOL) / atan(10)   for s < 10·VTOL,
///                  r(s) = 1                          for s ≥ 10·VTOL.
/// ```
///
/// `φ` is smooth at s = 0 (φ(0) = 1/(VTOL·atan 10)), so the force is a smooth function of V_t
/// there; `φ'(s)/s` is returned (not φ') because the tangent needs `φ'(s)/s · V_t V_tᵀ`, which
/// is finite at s = 0.
///
/// # Reference
/// $$F_t \leftarrow F_t \cdot \tfrac{2}{\pi}\arctan(|V_t|/V_{TOL}) \quad \text{if } |V_t| < 10\,V_{TOL}$$
/// [Paper eq. (5)].
///
/// **How the condition is read.** Taken literally, eq. (5) multiplies F_t by
/// (2/π)·atan(|V_t|/VTOL) inside the zone and by 1 outside, which jumps by
/// 1 − (2/π)·atan(10) = 6.3 % at |V_t| = 10·VTOL — the discontinuity the paper says the
/// procedure avoids. We keep the arctangent shape and the zone, and normalise the arctangent
/// by its value at the zone's end, atan(10), instead of by its limit π/2: r(s) is then
/// continuous (C⁰; r' drops from 1/(101·VTOL·atan 10) to 0 at 10·VTOL), r(s) ≤ 1, and r'(0) is
/// 1/(VTOL·atan 10) = 0.68/VTOL instead of the paper's 0.64/VTOL.
pub fn regularisation(s: Real, vtol: Real) -> (Real, Real) {
    if s >= 10.0 * vtol {
        return (1.0 / s, -1.0 / (s * s * s));
    }
    let x = s / vtol;
    // g(x) = atan(x)/x and h(x) = g'(x)/x = (x/(1+x²) − atan x)/x³; series near 0.
    let (g, h) = if x < 1e-3 {
        let x2 = x * x;
        (
            1.0 - x2 / 3.0 + x2 * x2 / 5.0,
            -2.0 / 3.0 + 4.0 * x2 / 5.0 - 6.0 * x2 * x2 / 7.0,
        )
    } else {
        let at = x.atan();
        (at / x, (x / (1.0 + x * x) - at) / (x * x * x))
    };
    // φ(s) = g(s/VTOL)/(VTOL atan10);  φ'(s)/s = h(s/VTOL)/(VTOL³ atan10).
    (g / (vtol * ATAN_10), h / (vtol * vtol * vtol * ATAN_10))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atan10_constant() {
        assert!((ATAN_10 - 10f64.atan()).abs() < 1e-15);
    }

    #[test]
    fn continuous_at_zone_end_and_series_matches() {
        let vtol = 1e-3;
        let s = 10.0 * vtol;
        let (below, _) = regularisation(s * (1.0 - 1e-12), vtol);
        let (above, _) = regularisation(s, vtol);
        // r(s) = φ s is continuous at 10 VTOL: both sides give 1.
        assert!((below * s - 1.0).abs() < 1e-10);
        assert!((above * s - 1.0).abs() < 1e-15);
        // Series and closed form agree across the switch at x = 1e-3.
        let (g0, h0) = regularisation(0.999_999e-3 * vtol, vtol);
        let (g1, h1) = regularisation(1.000_001e-3 * vtol, vtol);
        assert!((g0 - g1).abs() / g0 < 1e-9);
        assert!((h0 - h1).abs() / h0.abs() < 1e-6);
    }

    #[test]
    fn derivative_matches_finite_difference() {
        let vtol = 2e-3;
        for &s in &[1e-5, 3e-4, 4e-3, 1.5e-2, 0.3] {
            let e = 1e-7 * s;
            let (fp, _) = regularisation(s + e, vtol);
            let (fm, _) = regularisation(s - e, vtol);
            let (_, psi) = regularisation(s, vtol);
            let fd = (fp - fm) / (2.0 * e);
            assert!(
                (fd - psi * s).abs() <= 1e-6 * (fd.abs() + 1.0 / (vtol * vtol)),
                "s = {s}: fd {fd} vs {}",
                psi * s
            );
        }
    }
}
