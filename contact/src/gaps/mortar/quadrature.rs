//! Quadrature of the mortar integrals: Gauss–Legendre, the collapsed (Duffy) Gauss rule on
//! triangles, rules on the reference faces, and the adaptive rule on a mortar triangle.

use crate::gaps::FaceKind;
use crate::Real;

/// n-point Gauss–Legendre rule on [0, 1]: (points, weights), exact for polynomials of degree
/// 2n − 1. Nodes by Newton on the Legendre polynomial P_n from the Chebyshev guesses (to
/// round-off for the n ≤ 20 used here).
pub(crate) fn gauss_legendre(n: usize) -> (Vec<Real>, Vec<Real>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        let mut z = (std::f64::consts::PI * (i as Real + 0.75) / (n as Real + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(z) and P_n'(z) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as Real * z * p1 - (k - 1) as Real * p0) / k as Real;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pm = if n == 1 { 1.0 } else { p0 };
            dp = n as Real * (z * pn - pm) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() <= 1e-16 {
                break;
            }
        }
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        // Map [−1, 1] → [0, 1].
        x[i] = 0.5 * (1.0 - z);
        x[n - 1 - i] = 0.5 * (1.0 + z);
        w[i] = 0.5 * wi;
        w[n - 1 - i] = 0.5 * wi;
    }
    (x, w)
}

/// Collapsed Gauss rule on the unit triangle {ξ, η ≥ 0, ξ + η ≤ 1}: (ξ, η, weight) with
/// ξ = u, η = (1 − u) v, weight w_u w_v (1 − u) (weights sum to ½, the triangle's area).
///
/// # Derivation
/// A monomial ξ^a η^b (a + b ≤ p) becomes u^a (1 − u)^(b+1) v^b: degree ≤ p + 1 in u and
/// ≤ p in v, so n points per direction integrate total degree p = 2n − 2 exactly.
pub(crate) fn triangle_rule(n: usize) -> Vec<([Real; 2], Real)> {
    let (x, w) = gauss_legendre(n);
    let mut out = Vec::with_capacity(n * n);
    for (u, wu) in x.iter().zip(&w) {
        for (v, wv) in x.iter().zip(&w) {
            out.push(([*u, (1.0 - u) * v], wu * wv * (1.0 - u)));
        }
    }
    out
}

/// A rule on the reference face of `kind`: n × n Gauss on [−1, 1]² for quads (degree 2n − 1
/// per variable), the collapsed rule for triangles (total degree 2n − 2).
pub(crate) fn face_rule(kind: FaceKind, n: usize) -> Vec<([Real; 2], Real)> {
    if kind.is_triangle() {
        return triangle_rule(n);
    }
    let (x, w) = gauss_legendre(n);
    let mut out = Vec::with_capacity(n * n);
    for (a, wa) in x.iter().zip(&w) {
        for (b, wb) in x.iter().zip(&w) {
            out.push(([2.0 * a - 1.0, 2.0 * b - 1.0], 4.0 * wa * wb));
        }
    }
    out
}

/// Signed area of a plane triangle.
pub(crate) fn tri_area(t: &[[Real; 2]; 3]) -> Real {
    0.5 * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]))
}

/// The adaptive integration of a vector of functions over plane triangles.
pub(crate) struct Adaptive<'a> {
    /// The rule on the unit triangle (weights sum to ½) of the exact case.
    pub exact_rule: &'a [([Real; 2], Real)],
    /// The rule of the adaptive case (of high degree: few subdivisions on analytic
    /// integrands).
    pub rule: &'a [([Real; 2], Real)],
    /// A rule of lower degree whose difference from `rule` is the error estimate.
    pub check_rule: &'a [([Real; 2], Real)],
    /// Accepted error per unit area of a sub-triangle (max over the entries).
    pub tolerance: Real,
    /// Deepest subdivision (4^depth sub-triangles).
    pub max_depth: usize,
}

/// What an adaptive integration found.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct AdaptiveInfo {
    /// Sub-triangles integrated (the rule pair applied this many times).
    pub n_triangles: usize,
    /// Sum over the accepted sub-triangles of their error estimates (max over entries).
    pub error: Real,
    /// Sub-triangles accepted at `max_depth` above the tolerance.
    pub n_unconverged: usize,
}

impl Adaptive<'_> {
    /// Σ_q w_q 2|T| f(x_q) into `out` (added), f evaluated by `eval(point, values)`, which
    /// fills `values` (length `out.len()`) or returns false (a point that maps on no face).
    fn apply(
        &self,
        rule: &[([Real; 2], Real)],
        t: &[[Real; 2]; 3],
        eval: &mut dyn FnMut([Real; 2], &mut [Real]) -> bool,
        out: &mut [Real],
        scratch: &mut [Real],
    ) -> bool {
        let a2 = 2.0 * tri_area(t);
        for &(p, w) in rule {
            let l0 = 1.0 - p[0] - p[1];
            let x = [0, 1].map(|k| l0 * t[0][k] + p[0] * t[1][k] + p[1] * t[2][k]);
            if !eval(x, scratch) {
                return false;
            }
            for (o, s) in out.iter_mut().zip(scratch.iter()) {
                *o += w * a2 * s;
            }
        }
        true
    }

    /// ∫_T f added into `out`. With `exact` the rule `exact_rule` is applied once (it
    /// integrates the functions exactly); otherwise `rule` and `check_rule` are applied, and
    /// their difference (the error of the lower-degree rule, so an upper bound of the
    /// higher-degree one's on smooth integrands) must be at most `tolerance·|T|`, or at the
    /// values' round-off, or at most `floor` (an absolute error negligible for the whole
    /// face: slivers of clipping whose area is round-off); if not, the triangle is split
    /// into four by its mid-edges and each child is integrated alike (down to `max_depth`).
    /// False when a point maps on no face.
    pub fn integrate(
        &self,
        t: [[Real; 2]; 3],
        exact: bool,
        floor: Real,
        eval: &mut dyn FnMut([Real; 2], &mut [Real]) -> bool,
        out: &mut [Real],
        info: &mut AdaptiveInfo,
    ) -> bool {
        let m = out.len();
        let mut scratch = vec![0.0; m];
        if exact {
            info.n_triangles += 1;
            return self.apply(self.exact_rule, &t, eval, out, &mut scratch);
        }
        let mut q = vec![0.0; m];
        let mut c = vec![0.0; m];
        self.refine(t, 0, floor, eval, out, (&mut q, &mut c, &mut scratch), info)
    }

    fn refine(
        &self,
        t: [[Real; 2]; 3],
        depth: usize,
        floor: Real,
        eval: &mut dyn FnMut([Real; 2], &mut [Real]) -> bool,
        out: &mut [Real],
        work: (&mut [Real], &mut [Real], &mut [Real]),
        info: &mut AdaptiveInfo,
    ) -> bool {
        let (q, c, scratch) = work;
        q.fill(0.0);
        c.fill(0.0);
        info.n_triangles += 1;
        if !self.apply(self.rule, &t, eval, q, scratch)
            || !self.apply(self.check_rule, &t, eval, c, scratch)
        {
            return false;
        }
        let err = q
            .iter()
            .zip(c.iter())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, Real::max);
        let area = tri_area(&t).abs();
        let scale = q.iter().fold(0.0, |s: Real, v| s.max(v.abs()));
        let limit = (self.tolerance * area)
            .max(64.0 * Real::EPSILON * scale)
            .max(floor);
        if err <= limit || depth + 1 >= self.max_depth {
            if err > limit {
                info.n_unconverged += 1;
            }
            info.error += err;
            out.iter_mut().zip(q.iter()).for_each(|(o, x)| *o += x);
            return true;
        }
        let mid = |a: [Real; 2], b: [Real; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let (m01, m12, m20) = (mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0]));
        for child in [
            [t[0], m01, m20],
            [m01, t[1], m12],
            [m20, m12, t[2]],
            [m12, m20, m01],
        ] {
            if !self.refine(child, depth + 1, floor, eval, out, (q, c, scratch), info) {
                return false;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gauss–Legendre integrates x^k on [0, 1] exactly for k ≤ 2n − 1 (1/(k + 1)).
    #[test]
    fn gauss_legendre_degree() {
        for n in 1..=12 {
            let (x, w) = gauss_legendre(n);
            for k in 0..2 * n {
                let q: Real = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                assert!(
                    (q - 1.0 / (k as Real + 1.0)).abs() < 2e-15,
                    "n={n} k={k}: {q}"
                );
            }
        }
    }

    /// The collapsed rule integrates ξ^a η^b over the unit triangle exactly for a + b ≤ 2n − 2
    /// (a! b! / (a + b + 2)!).
    #[test]
    fn triangle_rule_degree() {
        let fact = |k: usize| (1..=k).map(|i| i as Real).product::<Real>();
        for n in 1..=8 {
            let rule = triangle_rule(n);
            for a in 0..=2 * n - 2 {
                for b in 0..=2 * n - 2 - a {
                    let q: Real = rule
                        .iter()
                        .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32))
                        .sum();
                    let exact = fact(a) * fact(b) / fact(a + b + 2);
                    assert!(
                        (q - exact).abs() < 1e-15,
                        "n={n} a={a} b={b}: {q} vs {exact}"
                    );
                }
            }
        }
    }

    /// A non-polynomial integrand (1/(2 + x + y) over a triangle, exact value by the closed
    /// form below) reaches the tolerance by subdivision, and its error estimate bounds the
    /// true error.
    #[test]
    fn adaptive_reaches_the_tolerance() {
        let (rule, check) = (triangle_rule(8), triangle_rule(6));
        let ad = Adaptive {
            exact_rule: &rule,
            rule: &rule,
            check_rule: &check,
            tolerance: 1e-13,
            max_depth: 12,
        };
        // ∫∫_{x,y≥0, x+y≤1} dx dy /(2 + x + y) = ∫_0^1 s/(2 + s) ds = 1 − 2 ln(3/2).
        let exact = 1.0 - 2.0 * (1.5f64).ln();
        let mut out = [0.0];
        let mut info = AdaptiveInfo::default();
        let mut f = |p: [Real; 2], v: &mut [Real]| {
            v[0] = 1.0 / (2.0 + p[0] + p[1]);
            true
        };
        assert!(ad.integrate(
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            false,
            0.0,
            &mut f,
            &mut out,
            &mut info
        ));
        assert!((out[0] - exact).abs() < 1e-13, "{} vs {exact}", out[0]);
        assert!((out[0] - exact).abs() <= info.error.max(1e-15));
        assert_eq!(info.n_unconverged, 0);
    }
}
