//! Gauss–Legendre rules on [−1, 1] and their tensor products.

use crate::Real;

/// 1-D Gauss–Legendre points and weights for 2 or 3 points (exact to degree 3 / 5).
pub fn gauss_1d(n: usize) -> &'static [(Real, Real)] {
    const G2: [(Real, Real); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    const G3: [(Real, Real); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    if n <= 2 {
        &G2
    } else {
        &G3
    }
}

/// Tensor-product rule on the cube [−1,1]³ with `n` points per direction (2 or 3).
pub fn hex_rule(n: usize) -> Vec<([Real; 3], Real)> {
    let g = gauss_1d(n);
    let mut out = Vec::with_capacity(g.len().pow(3));
    for &(z, wz) in g {
        for &(y, wy) in g {
            for &(x, wx) in g {
                out.push(([x, y, z], wx * wy * wz));
            }
        }
    }
    out
}

/// Tensor-product rule on the square [−1,1]² with `n` points per direction (2 or 3).
pub fn quad_rule(n: usize) -> Vec<([Real; 2], Real)> {
    let g = gauss_1d(n);
    let mut out = Vec::with_capacity(g.len().pow(2));
    for &(y, wy) in g {
        for &(x, wx) in g {
            out.push(([x, y], wx * wy));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_integrate_polynomials_exactly() {
        // ∫_{-1}^{1} x^4 dx = 2/5 (3-point rule is exact to degree 5); ∫ x^2 = 2/3 (2-point).
        let i4: Real = gauss_1d(3).iter().map(|(x, w)| w * x.powi(4)).sum();
        assert!((i4 - 0.4).abs() < 1e-15);
        let i2: Real = gauss_1d(2).iter().map(|(x, w)| w * x * x).sum();
        assert!((i2 - 2.0 / 3.0).abs() < 1e-15);
        let v: Real = hex_rule(3).iter().map(|(_, w)| w).sum();
        assert!((v - 8.0).abs() < 1e-14);
        let a: Real = quad_rule(2).iter().map(|(_, w)| w).sum();
        assert!((a - 4.0).abs() < 1e-14);
    }
}
