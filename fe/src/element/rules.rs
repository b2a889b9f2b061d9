//! Quadrature rules of the tetrahedra, wedges, pyramids and triangles, as static tables.
//!
//! Every rule has positive weights. Which rule each element uses, and why it integrates the
//! straight-sided element's stiffness and mass exactly, is stated in `docs/elements.md` and at
//! each element; the tests below check each rule's polynomial degree on monomials.
//!
//! # Reference
//! - Triangle degree 2 (3 points) and degree 4 (6 points, D. A. Dunavant, "High degree
//!   efficient symmetrical Gaussian quadrature rules for the triangle", IJNME 21 (1985)).
//! - Tetrahedron degree 1 (centroid), degree 2 (4 points, a = (5 − √5)/20) and degree 5
//!   (14 points, positive weights: Walkington, "Quadrature on simplices of arbitrary
//!   dimension", CMU 2000; also Keast 1986). The orbit values were solved to double
//!   precision by `fe/scripts/quadrature_rules.py`.
//! - Wedges: triangle rule × Gauss–Legendre in ζ. Pyramids: the conical (collapsed, Duffy)
//!   product rule: Gauss–Legendre in x̂, ŷ and in ζ ∈ [0, 1], the weight times (1 − ζ)²
//!   (Stroud, *Approximate calculation of multiple integrals*, 1971, §2.7).

use crate::Real;
use std::sync::OnceLock;

/// A rule: points in natural coordinates and weights.
pub type Rule = [([Real; 3], Real)];

/// A rule built once, on first use.
type Lazy = OnceLock<Vec<([Real; 3], Real)>>;

/// Gauss–Legendre points and weights on [−1, 1] with `n` = 1..=4 points (exact to degree 2n − 1).
pub fn gauss(n: usize) -> &'static [(Real, Real)] {
    const G1: [(Real, Real); 1] = [(0.0, 2.0)];
    const G2: [(Real, Real); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    const G3: [(Real, Real); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    const G4: [(Real, Real); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    match n {
        0 | 1 => &G1,
        2 => &G2,
        3 => &G3,
        _ => &G4,
    }
}

/// Triangle rules (ξ, η, weight) on the unit triangle (area ½).
pub fn triangle(degree: usize) -> &'static [([Real; 2], Real)] {
    const T2: [([Real; 2], Real); 3] = [
        ([1.0 / 6.0, 1.0 / 6.0], 1.0 / 6.0),
        ([2.0 / 3.0, 1.0 / 6.0], 1.0 / 6.0),
        ([1.0 / 6.0, 2.0 / 3.0], 1.0 / 6.0),
    ];
    const A1: Real = 0.445_948_490_915_964_7;
    const W1: Real = 0.111_690_794_839_005_57;
    const A2: Real = 0.091_576_213_509_770_92;
    const W2: Real = 0.054_975_871_827_661_095;
    const T4: [([Real; 2], Real); 6] = [
        ([A1, A1], W1),
        ([A1, 1.0 - 2.0 * A1], W1),
        ([1.0 - 2.0 * A1, A1], W1),
        ([A2, A2], W2),
        ([A2, 1.0 - 2.0 * A2], W2),
        ([1.0 - 2.0 * A2, A2], W2),
    ];
    if degree <= 2 {
        &T2
    } else {
        &T4
    }
}

/// Tetrahedron rules on the unit tetrahedron (volume 1/6): degree 1 (1 point), 2 (4 points)
/// or 5 (14 points) — the smallest of these that reaches `degree`.
pub fn tetrahedron(degree: usize) -> &'static Rule {
    const T1: [([Real; 3], Real); 1] = [([0.25, 0.25, 0.25], 1.0 / 6.0)];
    const A: Real = 0.138_196_601_125_010_5;
    const B: Real = 1.0 - 3.0 * A;
    const T2: [([Real; 3], Real); 4] = [
        ([A, A, A], 1.0 / 24.0),
        ([B, A, A], 1.0 / 24.0),
        ([A, B, A], 1.0 / 24.0),
        ([A, A, B], 1.0 / 24.0),
    ];
    static T5: Lazy = OnceLock::new();
    match degree {
        0 | 1 => &T1,
        2 => &T2,
        _ => T5.get_or_init(|| {
            const A1: Real = 0.092_735_250_310_891_2;
            const W1: Real = 0.012_248_840_519_393_66;
            const A2: Real = 0.310_885_919_263_300_6;
            const W2: Real = 0.018_781_320_953_002_64;
            const A3: Real = 0.045_503_704_125_649_6;
            const W3: Real = 0.007_091_003_462_846_911;
            let mut r = Vec::with_capacity(14);
            for (a, w) in [(A1, W1), (A2, W2)] {
                let b = 1.0 - 3.0 * a;
                r.extend([[a, a, a], [b, a, a], [a, b, a], [a, a, b]].map(|p| (p, w)));
            }
            // Orbit of (a, a, b, b) over the barycentric coordinates (L0, L1, L2, L3).
            let b = 0.5 - A3;
            for i in 0..4 {
                for j in i + 1..4 {
                    let mut l = [b; 4];
                    l[i] = A3;
                    l[j] = A3;
                    r.push(([l[1], l[2], l[3]], W3));
                }
            }
            r
        }),
    }
}

/// Wedge rule: the triangle rule of `tri_degree` × `n` Gauss points in ζ.
pub fn wedge(tri_degree: usize, n: usize) -> &'static Rule {
    static W: [Lazy; 2] = [OnceLock::new(), OnceLock::new()];
    let (slot, td, n) = if tri_degree <= 2 && n <= 2 {
        (0, 2, 2)
    } else {
        (1, 4, n.max(3))
    };
    W[slot].get_or_init(|| {
        let mut r = Vec::new();
        for &(z, wz) in gauss(n) {
            for &([x, y], w) in triangle(td) {
                r.push(([x, y, z], w * wz));
            }
        }
        r
    })
}

/// Conical product rule on the pyramid in collapsed coordinates (x̂, ŷ, ζ): `nxy` Gauss points
/// in x̂ and ŷ, `nz` in ζ ∈ [0, 1], weights × (1 − ζ)² (the Duffy Jacobian).
pub fn pyramid(nxy: usize, nz: usize) -> &'static Rule {
    static P: [Lazy; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    let (slot, nxy, nz) = match (nxy, nz) {
        (0..=2, 0..=3) => (0, 2, 3),
        (3, 0..=3) => (1, 3, 3),
        _ => (2, 3, 4),
    };
    P[slot].get_or_init(|| {
        let mut r = Vec::new();
        for &(t, wt) in gauss(nz) {
            let z = 0.5 * (1.0 + t);
            let s = 1.0 - z;
            for &(y, wy) in gauss(nxy) {
                for &(x, wx) in gauss(nxy) {
                    r.push(([x, y, z], wx * wy * 0.5 * wt * s * s));
                }
            }
        }
        r
    })
}

/// Tensor-product Gauss rule on the cube [−1, 1]³ with `n` = 2 or 3 points per direction.
pub fn hexahedron(n: usize) -> &'static Rule {
    static H: [Lazy; 2] = [OnceLock::new(), OnceLock::new()];
    let (slot, n) = if n <= 2 { (0, 2) } else { (1, 3) };
    H[slot].get_or_init(|| {
        let g = gauss(n);
        let mut out = Vec::with_capacity(n * n * n);
        for &(z, wz) in g {
            for &(y, wy) in g {
                for &(x, wx) in g {
                    out.push(([x, y, z], wx * wy * wz));
                }
            }
        }
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fact(n: u32) -> Real {
        (1..=n).map(Real::from).product()
    }

    /// ∫ over the unit simplex of ξ^i η^j ζ^k = i! j! k! / (i + j + k + 3)!.
    #[test]
    fn simplex_rules_reach_their_degree() {
        for (deg, rule) in [
            (1, tetrahedron(1)),
            (2, tetrahedron(2)),
            (5, tetrahedron(5)),
        ] {
            for i in 0..=deg {
                for j in 0..=deg - i {
                    for k in 0..=deg - i - j {
                        let q: Real = rule
                            .iter()
                            .map(|(p, w)| w * p[0].powi(i) * p[1].powi(j) * p[2].powi(k))
                            .sum();
                        let e = fact(i as u32) * fact(j as u32) * fact(k as u32)
                            / fact((i + j + k + 3) as u32);
                        assert!((q - e).abs() < 1e-16, "tet {deg}: {i} {j} {k}: {q} vs {e}");
                    }
                }
            }
        }
        for (deg, rule) in [(2, triangle(2)), (4, triangle(4))] {
            for i in 0..=deg {
                for j in 0..=deg - i {
                    let q: Real = rule
                        .iter()
                        .map(|(p, w)| w * p[0].powi(i) * p[1].powi(j))
                        .sum();
                    let e = fact(i as u32) * fact(j as u32) / fact((i + j + 2) as u32);
                    assert!((q - e).abs() < 1e-16, "tri {deg}: {i} {j}");
                }
            }
        }
        assert!(tetrahedron(5).len() == 14 && tetrahedron(5).iter().all(|(_, w)| *w > 0.0));
    }

    /// The pyramid rule (nxy, nz) integrates g(x̂, ŷ, ζ) (1 − ζ)² over [−1, 1]² × [0, 1]
    /// exactly for monomials x̂^i ŷ^j ζ^k with i, j ≤ 2 nxy − 1 and k ≤ 2 nz − 3:
    /// ∫ = c_i c_j B(k + 1, 3), c_i = 2/(i + 1) for even i, 0 for odd i.
    #[test]
    fn pyramid_rules_integrate_polynomials() {
        let beta = |a: u32, b: u32| fact(a - 1) * fact(b - 1) / fact(a + b - 1);
        let c = |n: u32| {
            if n % 2 == 0 {
                2.0 / (n + 1) as Real
            } else {
                0.0
            }
        };
        for (nxy, nz) in [(2, 3), (3, 3), (3, 4)] {
            let rule = pyramid(nxy, nz);
            assert_eq!(rule.len(), nxy * nxy * nz);
            for i in 0..2 * nxy as u32 {
                for j in 0..2 * nxy as u32 {
                    for k in 0..2 * nz as u32 - 2 {
                        let q: Real = rule
                            .iter()
                            .map(|(x, w)| {
                                w * x[0].powi(i as i32) * x[1].powi(j as i32) * x[2].powi(k as i32)
                            })
                            .sum();
                        let e = c(i) * c(j) * beta(k + 1, 3);
                        assert!(
                            (q - e).abs() < 1e-14,
                            "({nxy},{nz}) {i} {j} {k}: {q} vs {e}"
                        );
                    }
                }
            }
        }
        let v: Real = pyramid(3, 4).iter().map(|(_, w)| w).sum();
        assert!((v - 4.0 / 3.0).abs() < 1e-14);
        let v: Real = wedge(4, 3).iter().map(|(_, w)| w).sum();
        assert!((v - 1.0).abs() < 1e-15);
        assert!((hexahedron(3).iter().map(|(_, w)| w).sum::<Real>() - 8.0).abs() < 1e-14);
    }
}
