//! First derivative of a root with respect to a parameter of the matrices.

use super::Triplet;
use crate::cea::{CeaError, CeaMatrices, Cplx};
use faer::Mat;

/// The derivatives of the CEA matrices with respect to one parameter θ (`None`: that matrix
/// does not depend on θ). `c` is the derivative of the damping `C = B − C_f`.
#[derive(Debug, Clone, Default)]
pub struct MatrixDerivative {
    /// ∂M/∂θ (n×n).
    pub m: Option<Mat<f64>>,
    /// ∂(B − C_f)/∂θ (n×n).
    pub c: Option<Mat<f64>>,
    /// ∂K/∂θ (n×n).
    pub k: Option<Mat<f64>>,
    /// ∂G/∂θ (ng×n).
    pub g: Option<Mat<f64>>,
    /// ∂D/∂θ (n×ng).
    pub d: Option<Mat<f64>>,
}

impl MatrixDerivative {
    /// The central difference `(sys(θ + h) − sys(θ − h)) / 2h` of two systems of the same
    /// shape (a matrix present in one and absent in the other counts as zero there).
    ///
    /// # Errors
    /// Shapes that differ between the two systems.
    pub fn central_difference(
        plus: &CeaMatrices,
        minus: &CeaMatrices,
        h: f64,
    ) -> Result<Self, CeaError> {
        fn diff(
            what: &'static str,
            a: Option<&Mat<f64>>,
            b: Option<&Mat<f64>>,
            h: f64,
        ) -> Result<Option<Mat<f64>>, CeaError> {
            match (a, b) {
                (None, None) => Ok(None),
                (Some(a), Some(b)) => {
                    if a.nrows() != b.nrows() || a.ncols() != b.ncols() {
                        return Err(CeaError::Shape {
                            what,
                            rows: b.nrows(),
                            cols: b.ncols(),
                            expected_rows: a.nrows(),
                            expected_cols: a.ncols(),
                        });
                    }
                    Ok(Some(Mat::from_fn(a.nrows(), a.ncols(), |i, j| {
                        (a[(i, j)] - b[(i, j)]) / (2.0 * h)
                    })))
                }
                (Some(a), None) => Ok(Some(Mat::from_fn(a.nrows(), a.ncols(), |i, j| {
                    a[(i, j)] / (2.0 * h)
                }))),
                (None, Some(b)) => Ok(Some(Mat::from_fn(b.nrows(), b.ncols(), |i, j| {
                    -b[(i, j)] / (2.0 * h)
                }))),
            }
        }
        let damp = |s: &CeaMatrices| crate::cea::operator::damping(s);
        let (cp, cm) = (damp(plus), damp(minus));
        Ok(MatrixDerivative {
            m: diff("dM", Some(&plus.m), Some(&minus.m), h)?,
            c: diff("dC", cp.as_ref(), cm.as_ref(), h)?,
            k: diff("dK", Some(&plus.k), Some(&minus.k), h)?,
            g: diff("dG", plus.g.as_ref(), minus.g.as_ref(), h)?,
            d: diff("dD", plus.d.as_ref(), minus.d.as_ref(), h)?,
        })
    }
}

/// `xᴴ A y` for a real matrix A.
fn form(x: &[Cplx], a: &Mat<f64>, y: &[Cplx]) -> Cplx {
    let mut s = Cplx::new(0.0, 0.0);
    for j in 0..a.ncols() {
        if y[j] == Cplx::new(0.0, 0.0) {
            continue;
        }
        let mut col = Cplx::new(0.0, 0.0);
        for i in 0..a.nrows() {
            col += x[i].conj() * a[(i, j)];
        }
        s += col * y[j];
    }
    s
}

/// `∂p/∂θ` of the root of `t`.
///
/// # Reference
/// For `Q(p, θ) x = 0`, `yᴴ Q = 0` with a simple root p, differentiating `yᴴ Q(p(θ), θ) x = 0`
/// gives
/// $$\frac{\partial p}{\partial\theta} = -\frac{y^H\,\partial_\theta Q\,x}{y^H\,\partial_p Q\,x},
/// \qquad \partial_p Q = \begin{bmatrix}2pM + C & 0\\0&0\end{bmatrix},\quad
/// \partial_\theta Q = \begin{bmatrix}p^2 M' + pC' + K' & G'^T - D'\\ G' & 0\end{bmatrix}$$
/// (Lancaster 1964, *On eigenvalues of matrices dependent on a parameter*, Numer. Math. 6;
/// Tisseur 2000 for the nonlinear pencil). Near a coalescence (a double root) the
/// denominator → 0 and the derivative is unbounded: the returned `denominator` tells.
pub fn eigenvalue_derivative(sys: &CeaMatrices, t: &Triplet, dq: &MatrixDerivative) -> Sensitivity {
    let p = t.p;
    let c = crate::cea::operator::damping(sys);
    let mut den = p * 2.0 * form(&t.psi, &sys.m, &t.phi);
    if let Some(c) = &c {
        den += form(&t.psi, c, &t.phi);
    }
    let mut num = Cplx::new(0.0, 0.0);
    if let Some(m) = &dq.m {
        num += p * p * form(&t.psi, m, &t.phi);
    }
    if let Some(cc) = &dq.c {
        num += p * form(&t.psi, cc, &t.phi);
    }
    if let Some(k) = &dq.k {
        num += form(&t.psi, k, &t.phi);
    }
    if let Some(g) = &dq.g {
        // ψᴴ G'ᵀ ν + χᴴ G' φ
        num += form(&t.psi, &g.transpose().to_owned(), &t.nu);
        num += form(&t.chi, g, &t.phi);
    }
    if let Some(d) = &dq.d {
        num -= form(&t.psi, d, &t.nu);
    }
    let scale = (t.psi.iter().map(|z| z.norm_sqr()).sum::<f64>()
        * t.phi.iter().map(|z| z.norm_sqr()).sum::<f64>())
    .sqrt();
    Sensitivity {
        dp: -num / den,
        denominator: den.norm() / scale.max(f64::MIN_POSITIVE),
    }
}

/// The derivative of a root and how well it is defined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivity {
    /// ∂p/∂θ (its real part is ∂σ/∂θ, its imaginary part 2π ∂f/∂θ).
    pub dp: Cplx,
    /// `|ψᴴ(2pM + C)φ| / (‖ψ‖‖φ‖)`: small near a double root (coalescence), where the
    /// first derivative loses its meaning.
    pub denominator: f64,
}
