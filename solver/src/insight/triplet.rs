//! Right and left eigenvectors of one root of the constrained quadratic problem.

use crate::cea::operator::{check_inputs, damping};
use crate::cea::{CeaError, CeaMatrices, Cplx};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{c64, Mat};

/// A root `p` with its right eigenvector `x = [φ; ν]` and left eigenvector `y = [ψ; χ]` of
/// the bordered matrix
/// ```text
/// Q(p) = [p²M + pC + K   Gᵀ − D]
///        [G              0     ],      C = B − C_f,
/// ```
/// `Q(p) x = 0`, `yᴴ Q(p) = 0`. `φ` is the mode shape (displacements, length n), `ν` the
/// contact-force perturbation of each constraint row (length ng; the `N` of the module docs
/// of [`crate::cea`]); `ψ`, `χ` are their adjoint partners.
#[derive(Debug, Clone)]
pub struct Triplet {
    /// The root p, refined by the two-sided Rayleigh functional (Newton step) from the
    /// root it started at.
    pub p: Cplx,
    /// Right eigenvector, displacement part φ (unit 2-norm, largest entry real positive).
    pub phi: Vec<Cplx>,
    /// Right eigenvector, multiplier part ν (same scale as φ).
    pub nu: Vec<Cplx>,
    /// Left eigenvector, displacement part ψ.
    pub psi: Vec<Cplx>,
    /// Left eigenvector, multiplier part χ.
    pub chi: Vec<Cplx>,
    /// `‖Q(p) x‖ / (‖Q(p)‖_F ‖x‖)` of the right eigenvector at the refined p.
    pub residual: f64,
    /// The same for the left eigenvector.
    pub left_residual: f64,
}

/// The entries of `Q(p)` (dense, size n + ng).
pub(crate) fn bordered(sys: &CeaMatrices, c: Option<&Mat<f64>>, p: Cplx) -> Mat<c64> {
    let n = sys.m.nrows();
    let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
    let p2 = p * p;
    let (m, k, g, d) = (&sys.m, &sys.k, sys.g.as_ref(), sys.d.as_ref());
    Mat::<c64>::from_fn(n + ng, n + ng, |i, j| match (i < n, j < n) {
        (true, true) => p2 * m[(i, j)] + p * c.map_or(0.0, |c| c[(i, j)]) + k[(i, j)],
        (true, false) => c64::new(
            g.map_or(0.0, |g| g[(j - n, i)]) - d.map_or(0.0, |d| d[(i, j - n)]),
            0.0,
        ),
        (false, true) => c64::new(g.map_or(0.0, |g| g[(i - n, j)]), 0.0),
        (false, false) => c64::new(0.0, 0.0),
    })
}

/// `∂Q/∂p x = [(2pM + C) φ; 0]`.
fn dq_dp(sys: &CeaMatrices, c: Option<&Mat<f64>>, p: Cplx, x: &Mat<c64>) -> Mat<c64> {
    let n = sys.m.nrows();
    let phi = x.subrows(0, n);
    let mut out = Mat::<c64>::zeros(x.nrows(), 1);
    for j in 0..n {
        let xj = phi[(j, 0)];
        if xj == c64::new(0.0, 0.0) {
            continue;
        }
        for i in 0..n {
            let a = 2.0 * p * sys.m[(i, j)] + c.map_or(0.0, |c| c[(i, j)]);
            out[(i, 0)] += a * xj;
        }
    }
    out
}

fn norm(x: &Mat<c64>) -> f64 {
    (0..x.nrows())
        .map(|i| x[(i, 0)].norm_sqr())
        .sum::<f64>()
        .sqrt()
}

fn dot_h(y: &Mat<c64>, x: &Mat<c64>) -> Cplx {
    (0..x.nrows()).map(|i| y[(i, 0)].conj() * x[(i, 0)]).sum()
}

fn scale(x: &mut Mat<c64>, s: Cplx) {
    for i in 0..x.nrows() {
        x[(i, 0)] *= s;
    }
}

/// A deterministic start vector with no special structure (entries on the unit circle).
fn start(len: usize) -> Mat<c64> {
    Mat::<c64>::from_fn(len, 1, |i, _| {
        let a = 0.7548776662466927 * (i as f64 + 1.0);
        Cplx::from_polar(1.0, 2.0 * std::f64::consts::PI * a.fract())
    })
}

/// Right and left eigenvectors of the root nearest `p0` by inverse iteration on `Q(σ)`,
/// σ = `p0` (one complex LU of size n + ng, three solves each way), then p refined by the
/// two-sided Rayleigh functional `p ← σ − yᴴQ(σ)x / yᴴQ'(σ)x`.
///
/// # Reference
/// Inverse iteration for nonlinear eigenproblems and the two-sided Rayleigh functional:
/// Schreiber (2008), *Nonlinear eigenvalue problems: Newton-type methods and nonlinear
/// Rayleigh functionals*, ch. 4; Güttel & Tisseur (2017), *The nonlinear eigenvalue
/// problem*, Acta Numerica 26, §4.2.
///
/// # Errors
/// Input shapes (as [`crate::cea::complex_eigen`]); a non-finite factor.
pub fn eigen_triplet(sys: &CeaMatrices, p0: Cplx) -> Result<Triplet, CeaError> {
    let (n, ng) = check_inputs(sys)?;
    let c = damping(sys);
    let c = c.as_ref();
    // σ exactly at a computed root would make Q(σ) singular to round-off only in
    // exceptional cases; nudge it by a relative 1e-10 so the LU is always usable, which
    // the Newton step removes again.
    let sigma = p0 + Cplx::new(0.0, 1e-10 * p0.norm().max(1.0));
    let q = bordered(sys, c, sigma);
    let lu: PartialPivLu<c64> = q.partial_piv_lu();
    let u = lu.U();
    for i in 0..n + ng {
        if !u[(i, i)].norm().is_finite() || u[(i, i)].norm() == 0.0 {
            return Err(CeaError::SingularShift {
                re: sigma.re,
                im: sigma.im,
                ratio: 0.0,
            });
        }
    }
    let mut x = start(n + ng);
    let mut y = start(n + ng);
    for _ in 0..3 {
        let mut b = dq_dp(sys, c, sigma, &x);
        if norm(&b) == 0.0 {
            b = x.clone();
        }
        lu.solve_in_place(&mut b);
        let s = norm(&b);
        scale(&mut b, Cplx::new(1.0 / s, 0.0));
        x = b;
        // yᴴ Q'(σ) = (Q'(σ)ᴴ y)ᴴ; Q'(σ) has only the (2σM + C) block.
        let mut a = adjoint_dq_dp(sys, c, sigma, &y);
        if norm(&a) == 0.0 {
            a = y.clone();
        }
        lu.solve_adjoint_in_place(&mut a);
        let s = norm(&a);
        scale(&mut a, Cplx::new(1.0 / s, 0.0));
        y = a;
    }
    let num = dot_h(&y, &(&q * &x));
    let den = dot_h(&y, &dq_dp(sys, c, sigma, &x));
    let p = if den.norm() > 0.0 {
        sigma - num / den
    } else {
        p0
    };
    // Normalise φ to unit 2-norm with its largest entry real positive (the CEA's convention).
    let phi_norm = (0..n).map(|i| x[(i, 0)].norm_sqr()).sum::<f64>().sqrt();
    let imax = (0..n)
        .max_by(|&a, &b| x[(a, 0)].norm_sqr().total_cmp(&x[(b, 0)].norm_sqr()))
        .unwrap_or(0);
    if phi_norm > 0.0 && n > 0 {
        let ph = x[(imax, 0)].conj() / x[(imax, 0)].norm();
        scale(&mut x, ph / phi_norm);
    }
    let qp = bordered(sys, c, p);
    let qnorm = (0..n + ng)
        .flat_map(|j| (0..n + ng).map(move |i| (i, j)))
        .map(|(i, j)| qp[(i, j)].norm_sqr())
        .sum::<f64>()
        .sqrt();
    let residual = norm(&(&qp * &x)) / (qnorm * norm(&x));
    let left_residual = norm(&(qp.adjoint() * &y)) / (qnorm * norm(&y));
    Ok(Triplet {
        p,
        phi: (0..n).map(|i| x[(i, 0)]).collect(),
        nu: (n..n + ng).map(|i| x[(i, 0)]).collect(),
        psi: (0..n).map(|i| y[(i, 0)]).collect(),
        chi: (n..n + ng).map(|i| y[(i, 0)]).collect(),
        residual,
        left_residual,
    })
}

/// `Q'(σ)ᴴ y = [(2σM + C)ᴴ ψ; 0]`.
fn adjoint_dq_dp(sys: &CeaMatrices, c: Option<&Mat<f64>>, p: Cplx, y: &Mat<c64>) -> Mat<c64> {
    let n = sys.m.nrows();
    let mut out = Mat::<c64>::zeros(y.nrows(), 1);
    for i in 0..n {
        let mut acc = c64::new(0.0, 0.0);
        for j in 0..n {
            // (A^H)_{ij} = conj(A_{ji})
            let a = 2.0 * p * sys.m[(j, i)] + c.map_or(0.0, |c| c[(j, i)]);
            acc += a.conj() * y[(j, 0)];
        }
        out[(i, 0)] = acc;
    }
    out
}
