//! Right and left eigenvectors of one root of the constrained quadratic problem.

use crate::cea::operator::{check_inputs, damping};
use crate::cea::shift_invert::Elimination;
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

/// Right and left eigenvectors of the root nearest `p0` ([`TripletSolver::triplet`]; for
/// several roots of one system, make one [`TripletSolver`] and call it for each).
///
/// # Errors
/// Input shapes (as [`crate::cea::complex_eigen`]); a non-finite factor.
pub fn eigen_triplet(sys: &CeaMatrices, p0: Cplx) -> Result<Triplet, CeaError> {
    TripletSolver::new(sys)?.triplet(p0)
}

/// Right and left eigenvectors of roots of one system. What does not depend on the root is
/// made once: the damping `C = B − C_f` and, when the constraint has a well-conditioned slave
/// block, its null-space elimination with the reduced `ZᵀMT`, `ZᵀCT`, `ZᵀKT`
/// (`crate::cea::shift_invert::Elimination`: the complex LU per root is of size n − ng
/// instead of n + ng, about 5× cheaper on the 2 043-DOF brake with 550 gaps).
pub struct TripletSolver<'a> {
    sys: &'a CeaMatrices,
    c: Option<Mat<f64>>,
    n: usize,
    ng: usize,
    reduced: Option<Reduced>,
}

/// An inverse iteration's result: the Rayleigh-refined root (None: a zero denominator), the
/// right and the left eigenvector of the bordered problem.
type Iterated = (Option<Cplx>, Mat<c64>, Mat<c64>);

/// The null-space form: `R(σ) = σ² M_r + σ C_r + K_r`, `X_r = Zᵀ X T`.
struct Reduced {
    elim: Elimination,
    m: Mat<f64>,
    c: Option<Mat<f64>>,
    k: Mat<f64>,
}

impl<'a> TripletSolver<'a> {
    /// Checks the inputs and makes the root-independent parts.
    ///
    /// # Errors
    /// Input shapes (as [`crate::cea::complex_eigen`]).
    pub fn new(sys: &'a CeaMatrices) -> Result<Self, CeaError> {
        let (n, ng) = check_inputs(sys)?;
        let c = damping(sys);
        let reduced = Elimination::new(sys).map(|elim| Reduced {
            m: elim.reduce_matrix(&sys.m),
            c: c.as_ref().map(|c| elim.reduce_matrix(c)),
            k: elim.reduce_matrix(&sys.k),
            elim,
        });
        Ok(TripletSolver {
            sys,
            c,
            n,
            ng,
            reduced,
        })
    }

    /// The same without the null-space elimination: every root's LU is of the bordered
    /// `Q(σ)` (the reference route the elimination is checked against).
    ///
    /// # Errors
    /// Input shapes (as [`crate::cea::complex_eigen`]).
    pub fn bordered(sys: &'a CeaMatrices) -> Result<Self, CeaError> {
        let (n, ng) = check_inputs(sys)?;
        Ok(TripletSolver {
            sys,
            c: damping(sys),
            n,
            ng,
            reduced: None,
        })
    }

    /// `"null_space"` (the complex LU of size n − ng) or `"bordered"` (size n + ng: no
    /// constraint, or an ill-conditioned slave block).
    pub fn factorisation(&self) -> &'static str {
        if self.reduced.is_some() {
            "null_space"
        } else {
            "bordered"
        }
    }

    /// Right and left eigenvectors of the root nearest `p0` by inverse iteration on `Q(σ)`,
    /// σ = `p0` (one complex LU, three solves each way), then p refined by the two-sided
    /// Rayleigh functional `p ← σ − yᴴQ(σ)x / yᴴQ'(σ)x`.
    ///
    /// With the null-space elimination the iteration runs on `R(σ) = Zᵀ X(σ) T`,
    /// `X = σ²M + σC + K`: `x = [T q; ν]`, `y = [Z η; χ]` with `R(σ)⁻¹ R'(σ)` and its adjoint,
    /// and the multipliers follow from the first block row at the slave DOFs at the refined
    /// p (`ν = −A_s⁻¹ (X φ)_s`, `χ = −G_s⁻ᵀ (Xᴴ ψ)_s`, `A = Gᵀ − D`). `G T = 0` and
    /// `Zᵀ A = 0` make `yᴴ Q x = ηᴴ R q` and `yᴴ Q' x = ηᴴ R' q`, so the two routes compute the
    /// same vectors and Rayleigh step.
    ///
    /// # Reference
    /// Inverse iteration for nonlinear eigenproblems and the two-sided Rayleigh functional:
    /// Schreiber (2008), *Nonlinear eigenvalue problems: Newton-type methods and nonlinear
    /// Rayleigh functionals*, ch. 4; Güttel & Tisseur (2017), *The nonlinear eigenvalue
    /// problem*, Acta Numerica 26, §4.2. Null-space method for saddle-point systems: Benzi,
    /// Golub & Liesen (2005), *Numerical solution of saddle point problems*, Acta Numerica
    /// 14, §6.
    ///
    /// # Errors
    /// A singular or non-finite factor.
    pub fn triplet(&self, p0: Cplx) -> Result<Triplet, CeaError> {
        // σ exactly at a computed root would make Q(σ) singular to round-off only in
        // exceptional cases; nudge it by a relative 1e-10 so the LU is always usable, which
        // the Newton step removes again.
        let sigma = p0 + Cplx::new(0.0, 1e-10 * p0.norm().max(1.0));
        let (p, x, y) = match &self.reduced {
            Some(r) => self.iterate_reduced(r, sigma)?,
            None => self.iterate_bordered(sigma)?,
        };
        Ok(self.finish(p0, p, x, y))
    }

    /// Inverse iteration on the bordered `Q(σ)`: (p, x, y).
    fn iterate_bordered(&self, sigma: Cplx) -> Result<Iterated, CeaError> {
        let (sys, c, n, ng) = (self.sys, self.c.as_ref(), self.n, self.ng);
        let q = bordered(sys, c, sigma);
        let lu: PartialPivLu<c64> = q.partial_piv_lu();
        check_pivots(lu.U(), sigma)?;
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
        let p = (den.norm() > 0.0).then(|| sigma - num / den);
        Ok((p, x, y))
    }

    /// Inverse iteration on the null-space form `R(σ)`: (p, x, y) of the bordered problem.
    fn iterate_reduced(&self, r: &Reduced, sigma: Cplx) -> Result<Iterated, CeaError> {
        let (sys, c, n, ng) = (self.sys, self.c.as_ref(), self.n, self.ng);
        let nr = r.elim.reduced_size();
        let s2 = sigma * sigma;
        let rc = r.c.as_ref();
        let rs = Mat::<c64>::from_fn(nr, nr, |i, j| {
            s2 * r.m[(i, j)] + sigma * rc.map_or(0.0, |c| c[(i, j)]) + r.k[(i, j)]
        });
        let lu: PartialPivLu<c64> = rs.partial_piv_lu();
        check_pivots(lu.U(), sigma)?;
        // R'(σ) q = Zᵀ (2σM + C) T q and its adjoint Tᵀ (2σM + C)ᴴ Z η.
        let dp_times = |phi: &[Cplx]| -> Vec<Cplx> {
            combination(
                sys,
                c,
                2.0 * sigma,
                Cplx::new(1.0, 0.0),
                Cplx::new(0.0, 0.0),
                phi,
                false,
            )
        };
        let dp_adjoint = |psi: &[Cplx]| -> Vec<Cplx> {
            let one = Cplx::new(1.0, 0.0);
            combination(
                sys,
                c,
                (2.0 * sigma).conj(),
                one,
                Cplx::new(0.0, 0.0),
                psi,
                true,
            )
        };
        let mut q = column(&start(nr));
        let mut eta = column(&start(nr));
        for _ in 0..3 {
            let mut b = r.elim.restrict_left(&dp_times(&r.elim.expand_right(&q)));
            if vnorm(&b) == 0.0 {
                b = q.clone();
            }
            q = solve_normalised(&lu, b, false);
            let mut a = r
                .elim
                .restrict_right(&dp_adjoint(&r.elim.expand_left(&eta)));
            if vnorm(&a) == 0.0 {
                a = eta.clone();
            }
            eta = solve_normalised(&lu, a, true);
        }
        let phi = r.elim.expand_right(&q);
        let psi = r.elim.expand_left(&eta);
        // ψᴴ X(σ) φ = ηᴴ R(σ) q, ψᴴ (2σM + C) φ = ηᴴ R'(σ) q.
        let num = vdot(&psi, &x_times(sys, c, sigma, &phi));
        let den = vdot(&psi, &dp_times(&phi));
        let p = (den.norm() > 0.0).then(|| sigma - num / den);
        let at = p.unwrap_or(sigma);
        // The multipliers at the refined root.
        let xphi = x_times(sys, c, at, &phi);
        let nu = r.elim.multipliers(&xphi, false);
        let xpsi = x_adjoint_times(sys, c, at, &psi);
        let chi = r.elim.multipliers(&xpsi, true);
        let x = Mat::<c64>::from_fn(n + ng, 1, |i, _| if i < n { phi[i] } else { nu[i - n] });
        let mut y = Mat::<c64>::from_fn(n + ng, 1, |i, _| if i < n { psi[i] } else { chi[i - n] });
        let s = norm(&y);
        scale(&mut y, Cplx::new(1.0 / s, 0.0));
        Ok((p, x, y))
    }

    /// Normalises x (φ unit 2-norm, largest entry real positive) and measures both residuals
    /// at p.
    fn finish(&self, p0: Cplx, p: Option<Cplx>, mut x: Mat<c64>, y: Mat<c64>) -> Triplet {
        let (sys, c, n, ng) = (self.sys, self.c.as_ref(), self.n, self.ng);
        let p = p.unwrap_or(p0);
        // Normalise φ to unit 2-norm with its largest entry real positive (the CEA's
        // convention).
        let phi_norm = (0..n).map(|i| x[(i, 0)].norm_sqr()).sum::<f64>().sqrt();
        let imax = (0..n)
            .max_by(|&a, &b| x[(a, 0)].norm_sqr().total_cmp(&x[(b, 0)].norm_sqr()))
            .unwrap_or(0);
        if phi_norm > 0.0 && n > 0 {
            let ph = x[(imax, 0)].conj() / x[(imax, 0)].norm();
            scale(&mut x, ph / phi_norm);
        }
        let (phi, nu) = (
            column(&x.subrows(0, n).to_owned()),
            column(&x.subrows(n, ng).to_owned()),
        );
        let (psi, chi) = (
            column(&y.subrows(0, n).to_owned()),
            column(&y.subrows(n, ng).to_owned()),
        );
        // ‖Q(p)‖_F² = ‖X(p)‖_F² + ‖Gᵀ − D‖_F² + ‖G‖_F².
        let mut q2 = 0.0;
        for j in 0..n {
            for i in 0..n {
                let v = p * p * sys.m[(i, j)] + p * c.map_or(0.0, |c| c[(i, j)]) + sys.k[(i, j)];
                q2 += v.norm_sqr();
            }
        }
        if let Some(g) = &sys.g {
            for j in 0..n {
                for i in 0..ng {
                    let a = g[(i, j)] - sys.d.as_ref().map_or(0.0, |d| d[(j, i)]);
                    q2 += a * a + g[(i, j)] * g[(i, j)];
                }
            }
        }
        let qnorm = q2.sqrt();
        // Q(p) x = [X φ + A ν; G φ], Q(p)ᴴ y = [Xᴴ ψ + Gᵀ χ; Aᵀ ψ].
        let mut rx = x_times(sys, c, p, &phi);
        let mut ry = x_adjoint_times(sys, c, p, &psi);
        let mut r2x = 0.0;
        let mut r2y = 0.0;
        if let Some(g) = &sys.g {
            for k in 0..ng {
                let (mut gphi, mut apsi) = (Cplx::new(0.0, 0.0), Cplx::new(0.0, 0.0));
                for i in 0..n {
                    let a = g[(k, i)] - sys.d.as_ref().map_or(0.0, |d| d[(i, k)]);
                    rx[i] += a * nu[k];
                    ry[i] += g[(k, i)] * chi[k];
                    gphi += g[(k, i)] * phi[i];
                    apsi += a * psi[i];
                }
                r2x += gphi.norm_sqr();
                r2y += apsi.norm_sqr();
            }
        }
        r2x += rx.iter().map(|z| z.norm_sqr()).sum::<f64>();
        r2y += ry.iter().map(|z| z.norm_sqr()).sum::<f64>();
        let residual = r2x.sqrt() / (qnorm * norm(&x));
        let left_residual = r2y.sqrt() / (qnorm * norm(&y));
        Triplet {
            p,
            phi,
            nu,
            psi,
            chi,
            residual,
            left_residual,
        }
    }
}

fn check_pivots(u: faer::MatRef<'_, c64>, sigma: Cplx) -> Result<(), CeaError> {
    for i in 0..u.nrows() {
        if !u[(i, i)].norm().is_finite() || u[(i, i)].norm() == 0.0 {
            return Err(CeaError::SingularShift {
                re: sigma.re,
                im: sigma.im,
                ratio: 0.0,
            });
        }
    }
    Ok(())
}

/// The first column of a one-column matrix as a vector.
fn column(x: &Mat<c64>) -> Vec<Cplx> {
    (0..x.nrows()).map(|i| x[(i, 0)]).collect()
}

fn vnorm(x: &[Cplx]) -> f64 {
    x.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

fn vdot(y: &[Cplx], x: &[Cplx]) -> Cplx {
    y.iter().zip(x).map(|(a, b)| a.conj() * b).sum()
}

/// `lu⁻¹ b` (or `lu⁻ᴴ b`), scaled to unit norm.
fn solve_normalised(lu: &PartialPivLu<c64>, b: Vec<Cplx>, adjoint: bool) -> Vec<Cplx> {
    let mut m = Mat::<c64>::from_fn(b.len(), 1, |i, _| b[i]);
    if adjoint {
        lu.solve_adjoint_in_place(&mut m);
    } else {
        lu.solve_in_place(&mut m);
    }
    let s = norm(&m);
    (0..b.len()).map(|i| m[(i, 0)] / s).collect()
}

/// `(a M + b C + k K) x` for a complex vector x, or with Mᵀ, Cᵀ, Kᵀ when `transposed` (M, C, K
/// real: their products with Re x and Im x as two columns; a zero coefficient skips its
/// product).
#[allow(clippy::too_many_arguments)]
fn combination(
    sys: &CeaMatrices,
    c: Option<&Mat<f64>>,
    a: Cplx,
    b: Cplx,
    k: Cplx,
    x: &[Cplx],
    transposed: bool,
) -> Vec<Cplx> {
    let xr = Mat::<f64>::from_fn(x.len(), 2, |i, j| if j == 0 { x[i].re } else { x[i].im });
    let zero = Cplx::new(0.0, 0.0);
    let mut out = vec![zero; x.len()];
    for (coef, mat) in [(a, Some(&sys.m)), (b, c), (k, Some(&sys.k))] {
        let Some(mat) = mat.filter(|_| coef != zero) else {
            continue;
        };
        let y = if transposed {
            mat.transpose() * &xr
        } else {
            mat * &xr
        };
        for (i, o) in out.iter_mut().enumerate() {
            *o += coef * Cplx::new(y[(i, 0)], y[(i, 1)]);
        }
    }
    out
}

/// `X(p) x = (p²M + pC + K) x`.
fn x_times(sys: &CeaMatrices, c: Option<&Mat<f64>>, p: Cplx, x: &[Cplx]) -> Vec<Cplx> {
    combination(sys, c, p * p, p, Cplx::new(1.0, 0.0), x, false)
}

/// `X(p)ᴴ x = (p̄²Mᵀ + p̄Cᵀ + Kᵀ) x`.
fn x_adjoint_times(sys: &CeaMatrices, c: Option<&Mat<f64>>, p: Cplx, x: &[Cplx]) -> Vec<Cplx> {
    let pc = p.conj();
    combination(sys, c, pc * pc, pc, Cplx::new(1.0, 0.0), x, true)
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
