//! Input checks and the contact operator shared by the exact and projected solves.

use super::{check_finite, CeaError, CeaMatrices, Cplx};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

fn shape(what: &'static str, a: &Mat<f64>, r: usize, c: usize) -> Result<(), CeaError> {
    if a.nrows() != r || a.ncols() != c {
        return Err(CeaError::Shape {
            what,
            rows: a.nrows(),
            cols: a.ncols(),
            expected_rows: r,
            expected_cols: c,
        });
    }
    check_finite(what, a.as_ref())
}

/// Checks every matrix's shape and entries; returns (n, ng).
pub(crate) fn check_inputs(sys: &CeaMatrices) -> Result<(usize, usize), CeaError> {
    let n = sys.m.nrows();
    shape("M", &sys.m, n, n)?;
    shape("K", &sys.k, n, n)?;
    let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
    if let Some(g) = &sys.g {
        shape("G", g, ng, n)?;
    }
    if let Some(b) = &sys.b {
        shape("B", b, n, n)?;
    }
    if let Some(c) = &sys.c_f {
        shape("C_f", c, n, n)?;
    }
    if let Some(d) = &sys.d {
        shape("D", d, n, ng)?;
    }
    if ng > 0 && ng >= n {
        return Err(CeaError::Shape {
            what: "G (needs fewer rows than columns)",
            rows: ng,
            cols: n,
            expected_rows: n.saturating_sub(1),
            expected_cols: n,
        });
    }
    Ok((n, ng))
}

/// The damping of the linearised problem, `C = B − C_f` (`None` when both are absent).
pub(crate) fn damping(sys: &CeaMatrices) -> Option<Mat<f64>> {
    match (&sys.b, &sys.c_f) {
        (None, None) => None,
        (Some(b), None) => Some(b.clone()),
        (None, Some(c)) => Some(-c),
        (Some(b), Some(c)) => Some(b - c),
    }
}

/// Cholesky factor of a symmetric positive definite matrix; `what` names it in the error.
pub(crate) fn cholesky(
    what: &'static str,
    a: &Mat<f64>,
) -> Result<faer::linalg::solvers::Llt<f64>, CeaError> {
    a.llt(Side::Lower).map_err(|e| match e {
        faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
            CeaError::NotPositiveDefinite {
                what,
                n: a.nrows(),
                pivot: index,
            }
        }
    })
}

/// `Y = M⁻¹ Gᵀ` by a Cholesky factorisation of M.
#[allow(non_snake_case)]
pub(crate) fn mass_solve(M: &Mat<f64>, Gt: &Mat<f64>) -> Result<Mat<f64>, CeaError> {
    let llt = cholesky("M", M)?;
    let mut Y = Gt.clone();
    llt.solve_in_place(&mut Y);
    Ok(Y)
}

/// Smallest/largest |pivot| of an LU's U (`abs` the pivot's modulus); 0 when the largest is
/// 0 or not finite.
pub(crate) fn pivot_ratio<T: faer::traits::ComplexField>(
    u: faer::MatRef<'_, T>,
    abs: impl Fn(&T) -> f64,
) -> f64 {
    let (mut pmin, mut pmax) = (f64::INFINITY, 0.0f64);
    for i in 0..u.nrows().min(u.ncols()) {
        let a = abs(&u[(i, i)]);
        pmin = pmin.min(a);
        pmax = pmax.max(a);
    }
    if pmax > 0.0 && pmax.is_finite() {
        pmin / pmax
    } else {
        0.0
    }
}

/// The oblique projector `P = I − A S⁻¹ G M⁻¹`, `A = Gᵀ − D`, `S = G M⁻¹ A`
/// (see [`super::reduce`] for its derivation).
pub(crate) struct ContactProjector {
    /// Y = M⁻¹Gᵀ (n×ng).
    y: Mat<f64>,
    /// A = Gᵀ − D (n×ng).
    pub(crate) a: Mat<f64>,
    lu: faer::linalg::solvers::PartialPivLu<f64>,
}

impl ContactProjector {
    /// Builds P from `Y = M⁻¹Gᵀ`, `Gᵀ` and `D`; fails when `S` is singular.
    #[allow(non_snake_case)]
    pub(crate) fn new(Y: Mat<f64>, Gt: &Mat<f64>, D: &Mat<f64>) -> Result<Self, CeaError> {
        let ng = Gt.ncols();
        let A = Gt - D;
        let S = Y.transpose() * &A;
        let lu = S.partial_piv_lu();
        let pr = pivot_ratio(lu.U(), |x: &f64| x.abs());
        if pr.is_nan() || pr <= 1e3 * f64::EPSILON {
            return Err(CeaError::SingularContactOperator { ng, ratio: pr });
        }
        Ok(ContactProjector { y: Y, a: A, lu })
    }

    /// `W = S⁻¹ Yᵀ Z` (ng×k), so that `P Z = Z − A W`.
    #[allow(non_snake_case)]
    pub(crate) fn coefficients(&self, Z: &Mat<f64>) -> Mat<f64> {
        let mut W = self.y.transpose() * Z;
        self.lu.solve_in_place(&mut W);
        W
    }

    /// `P Z`.
    #[allow(non_snake_case)]
    pub(crate) fn apply(&self, Z: Mat<f64>) -> Mat<f64> {
        let W = self.coefficients(&Z);
        Z - &self.a * &W
    }
}

/// m complex vectors of length n as 2m real columns (column 2j the real parts of vector j,
/// 2j + 1 its imaginary parts; `z(j, i)` is entry i of vector j), so that a real matrix
/// multiplies them all in one product.
pub(crate) fn real_columns(n: usize, m: usize, z: impl Fn(usize, usize) -> Cplx) -> Mat<f64> {
    Mat::from_fn(n, 2 * m, |i, c| {
        let v = z(c / 2, i);
        if c % 2 == 0 {
            v.re
        } else {
            v.im
        }
    })
}

/// Entry i of complex vector j of a [`real_columns`] matrix.
pub(crate) fn complex_at(x: &Mat<f64>, i: usize, j: usize) -> Cplx {
    Cplx::new(x[(i, 2 * j)], x[(i, 2 * j + 1)])
}

/// The 2-norm of complex vector j of a [`real_columns`] matrix.
pub(crate) fn complex_norm(x: &Mat<f64>, j: usize) -> f64 {
    (0..x.nrows())
        .map(|i| x[(i, 2 * j)].powi(2) + x[(i, 2 * j + 1)].powi(2))
        .sum::<f64>()
        .sqrt()
}
