//! Lowest eigenpairs of K x = λ M x: dense (Cholesky of M) for small problems, shift-invert
//! block Lanczos with full reorthogonalisation for large ones.

use super::partition::Sparse;
use crate::error::ReductionError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatMut, MatRef, Par, Side};
use squeal_meshes::Real;

/// Which eigenpairs are wanted: all λ below `lambda_max` (if given), at most `n_max` (if given).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Want {
    pub lambda_max: Option<Real>,
    pub n_max: Option<usize>,
}

/// Eigenpairs in ascending order, vectors M-orthonormal.
pub(crate) struct Eigenpairs {
    pub values: Vec<Real>,
    pub vectors: Mat<Real>,
    /// Krylov dimension used (0 for dense).
    pub krylov_dim: usize,
    /// Right-hand sides solved with the factorisation (0 for dense).
    pub n_solves: usize,
    /// Seconds spent in the solves (Lanczos only).
    pub solve_s: Real,
    /// Seconds spent reorthogonalising against the basis (Lanczos only).
    pub orth_s: Real,
    /// Seconds spent in the M-orthonormalisation of new blocks, with their M products (Lanczos only).
    pub qr_s: Real,
}

fn eig_err(what: &str, n: usize, detail: impl Into<String>) -> ReductionError {
    ReductionError::Eigen {
        what: what.to_string(),
        n,
        detail: detail.into(),
    }
}

/// Number of leading entries of the ascending `values` that `want` keeps.
fn n_kept(values: &[Real], want: Want) -> usize {
    let below = match want.lambda_max {
        Some(l) => values.iter().take_while(|&&v| v <= l).count(),
        None => values.len(),
    };
    want.n_max.map_or(below, |n| n.min(below))
}

/// Eigenvalues (unsorted) and eigenvectors of a dense symmetric matrix.
///
/// The matrix is scaled to unit max-norm first: faer 0.24.4's `self_adjoint_eigen` lost
/// accuracy on unscaled stiffness-like matrices here (reconstruction error 1.7e-5 relative for a
/// 168-DOF plate pencil with norm 4e12, 3e-15 after scaling).
fn sym_eigen(a: Mat<Real>, what: &str) -> Result<(Vec<Real>, Mat<Real>), ReductionError> {
    let n = a.nrows();
    let scale = a.norm_max();
    if !scale.is_finite() {
        return Err(eig_err(what, n, "matrix has a non-finite entry"));
    }
    if scale == 0.0 {
        return Ok((vec![0.0; n], Mat::identity(n, n)));
    }
    let a = a * faer::Scale(1.0 / scale);
    let evd = a
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| eig_err(what, n, format!("dense self-adjoint eigen failed: {e:?}")))?;
    let values = evd.S().column_vector().iter().map(|&v| v * scale).collect();
    Ok((values, evd.U().to_owned()))
}

/// All eigenpairs of the dense symmetric pencil (k, m), ascending, vectors M-orthonormal.
///
/// Reduces to a standard problem with the Cholesky factor of m: C = L⁻¹ K L⁻ᵀ, x = L⁻ᵀ y.
pub(crate) fn dense_all(
    k: MatRef<'_, Real>,
    m: MatRef<'_, Real>,
    what: &str,
) -> Result<(Vec<Real>, Mat<Real>), ReductionError> {
    let n = k.nrows();
    let llt = m
        .llt(Side::Lower)
        .map_err(|e| ReductionError::Factorization {
            what: format!("mass matrix of {what}"),
            n,
            detail: format!("{e:?}"),
        })?;
    let l = llt.L();
    let mut c = k.to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    let mut ct = c.transpose().to_owned();
    solve_lower_triangular_in_place(l, ct.as_mut(), Par::Seq);
    let c = Mat::<Real>::from_fn(n, n, |i, j| 0.5 * (ct[(i, j)] + ct[(j, i)]));
    let (s, u) = sym_eigen(c, what)?;
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| s[a].total_cmp(&s[b]));
    let values: Vec<Real> = order.iter().map(|&i| s[i]).collect();
    let mut x = Mat::<Real>::from_fn(n, n, |i, j| u[(i, order[j])]);
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    Ok((values, x))
}

/// The wanted lowest eigenpairs of the dense pencil (k, m).
pub(crate) fn dense(
    k: MatRef<'_, Real>,
    m: MatRef<'_, Real>,
    want: Want,
    what: &str,
) -> Result<Eigenpairs, ReductionError> {
    let (values, x) = dense_all(k, m, what)?;
    let keep = n_kept(&values, want);
    Ok(Eigenpairs {
        values: values[..keep].to_vec(),
        vectors: x.subcols(0, keep).to_owned(),
        krylov_dim: 0,
        n_solves: 0,
        solve_s: 0.0,
        orth_s: 0.0,
        qr_s: 0.0,
    })
}

/// Parameters of the block Lanczos iteration.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LanczosParams {
    pub block: usize,
    pub max_dim: usize,
    pub tol: Real,
}

/// Deterministic pseudo-random starting block (xorshift64*).
fn random_block(n: usize, p: usize, seed: u64) -> Mat<Real> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    Mat::from_fn(n, p, |_, _| {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        let r = s.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (r >> 11) as Real / (1u64 << 53) as Real - 0.5
    })
}

/// M-orthonormalises the block `w` in place (Cholesky QR, twice); returns (M w, R) with
/// w_in = w_out R, or `None` if the block is numerically rank deficient.
fn chol_qr(w: &mut Mat<Real>, m: &Sparse) -> Option<(Mat<Real>, Mat<Real>)> {
    let p = w.ncols();
    let mut r_total = Mat::<Real>::identity(p, p);
    let mut mw = super::partition::sym_spmm(m, w.as_ref());
    for _ in 0..2 {
        let g = super::partition::at_b(w.as_ref(), mw.as_ref());
        let g = Mat::<Real>::from_fn(p, p, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
        let llt = g.llt(Side::Lower).ok()?;
        let l = llt.L();
        let dmax = (0..p).map(|i| l[(i, i)]).fold(0.0, Real::max);
        let dmin = (0..p).map(|i| l[(i, i)]).fold(Real::INFINITY, Real::min);
        // NaN-safe: also rejects a NaN diagonal.
        if dmin.is_nan() || dmin <= 1e-10 * dmax {
            return None;
        }
        // w ← w L⁻ᵀ  ⇔  wᵀ ← L⁻¹ wᵀ
        let mut wt = w.transpose().to_owned();
        solve_lower_triangular_in_place(l, wt.as_mut(), Par::Seq);
        *w = wt.transpose().to_owned();
        let mut mwt = mw.transpose().to_owned();
        solve_lower_triangular_in_place(l, mwt.as_mut(), Par::Seq);
        mw = mwt.transpose().to_owned();
        r_total = l.transpose() * &r_total;
    }
    Some((mw, r_total))
}

/// Krylov basis Q (M-orthonormal columns) and M Q, stored contiguously so that projections
/// against the whole basis are single matrix products.
struct Basis {
    q: Mat<Real>,
    mq: Mat<Real>,
    len: usize,
}

impl Basis {
    fn new(n: usize, cap: usize) -> Self {
        Self {
            q: Mat::zeros(n, cap),
            mq: Mat::zeros(n, cap),
            len: 0,
        }
    }

    fn push(&mut self, q: MatRef<'_, Real>, mq: MatRef<'_, Real>) {
        let (n, p) = (q.nrows(), q.ncols());
        if self.len + p > self.q.ncols() {
            let cap = (2 * self.q.ncols()).max(self.len + p);
            let mut nq = Mat::<Real>::zeros(n, cap);
            let mut nmq = Mat::<Real>::zeros(n, cap);
            nq.subcols_mut(0, self.len)
                .copy_from(self.q.subcols(0, self.len));
            nmq.subcols_mut(0, self.len)
                .copy_from(self.mq.subcols(0, self.len));
            self.q = nq;
            self.mq = nmq;
        }
        self.q.subcols_mut(self.len, p).copy_from(q);
        self.mq.subcols_mut(self.len, p).copy_from(mq);
        self.len += p;
    }

    /// w ← w − Q (MQ)ᵀ w; returns the coefficients (MQ)ᵀ w (len × p).
    fn project_out(&self, w: &mut Mat<Real>) -> Mat<Real> {
        let par = faer::get_global_parallelism();
        let c = super::partition::at_b(self.mq.subcols(0, self.len), w.as_ref());
        faer::linalg::matmul::matmul(
            w.as_mut(),
            faer::Accum::Add,
            self.q.subcols(0, self.len),
            c.as_ref(),
            -1.0,
            par,
        );
        c
    }
}

/// Lowest eigenpairs of K x = λ M x by block Lanczos on the operator (K − σM)⁻¹ M, whose
/// eigenvalues θ = 1/(λ − σ) are largest for the wanted λ. `solve` applies (K − σM)⁻¹ in place.
///
/// Full reorthogonalisation (classical Gram–Schmidt, twice) against the whole basis; the
/// projected matrix T = QᵀM(K − σM)⁻¹MQ is block tridiagonal, its diagonal blocks from the
/// projection coefficients and its off-diagonal blocks from the Cholesky-QR of each new block.
/// A Ritz pair (θ, Qs) has residual norm ‖B_j s_last‖ (B_j the last QR factor).
pub(crate) fn lanczos(
    solve: &(dyn Fn(MatMut<'_, Real>) + Sync),
    m: &Sparse,
    sigma: Real,
    want: Want,
    params: LanczosParams,
    what: &str,
    interrupt: &squeal_fe::Interrupt,
) -> Result<Eigenpairs, ReductionError> {
    let n = m.nrows();
    let p = params.block.min(n).max(1);
    let max_dim = params.max_dim.min(n);
    let initial_cap = (want.n_max.unwrap_or(4 * p) * 3 + 2 * p).min(max_dim + p);
    let mut basis = Basis::new(n, initial_cap);
    let mut t = Mat::<Real>::zeros(max_dim + p, max_dim + p);
    let mut n_solves = 0;
    let (mut solve_s, mut orth_s, mut qr_s) = (0.0, 0.0, 0.0);
    let mut w = random_block(n, p, 1);
    let (mw, _) = chol_qr(&mut w, m).ok_or_else(|| eig_err(what, n, "degenerate random start"))?;
    basis.push(w.as_ref(), mw.as_ref());
    let theta_min = want.lambda_max.map(|l| 1.0 / (l - sigma));
    let mut step = 0usize;
    loop {
        if interrupt.is_set() {
            return Err(ReductionError::Interrupted {
                during: "the fixed-interface Lanczos iterations",
            });
        }
        let j = step;
        let dim = basis.len;
        let mut w = basis.mq.subcols(dim - p, p).to_owned();
        let clock = std::time::Instant::now();
        solve(w.as_mut());
        solve_s += clock.elapsed().as_secs_f64();
        n_solves += p;
        let clock = std::time::Instant::now();
        let c = basis.project_out(&mut w);
        let c2 = basis.project_out(&mut w);
        // Diagonal block A_j (both passes); the block above it pairs with the previous B.
        for a in 0..p {
            for b in 0..p {
                t[(j * p + a, j * p + b)] = c[(j * p + a, b)] + c2[(j * p + a, b)];
                if j > 0 {
                    t[((j - 1) * p + a, j * p + b)] = c[((j - 1) * p + a, b)];
                }
            }
        }
        for a in 0..dim {
            for b in 0..a {
                let v = 0.5 * (t[(a, b)] + t[(b, a)]);
                t[(a, b)] = v;
                t[(b, a)] = v;
            }
        }
        orth_s += clock.elapsed().as_secs_f64();
        let clock = std::time::Instant::now();
        let next = chol_qr(&mut w, m);
        qr_s += clock.elapsed().as_secs_f64();
        let b_j = match &next {
            Some((_, r)) => r.clone(),
            None => Mat::<Real>::zeros(p, p),
        };
        let exhausted = dim + p > max_dim || (next.is_none() && dim + p > n);
        // Solving the projected problem costs O(dim³): do it less often as dim grows.
        if !exhausted && j >= 8 && j % (j / 8) != 0 {
            push_next(&mut basis, &mut t, next, w, p, m, what)?;
            step += 1;
            continue;
        }
        let tj = t.submatrix(0, 0, dim, dim).to_owned();
        let (s, u) = sym_eigen(tj, what)?;
        let mut order: Vec<usize> = (0..dim).collect();
        order.sort_by(|&a, &b| s[b].total_cmp(&s[a])); // θ descending
        let theta_scale = s.iter().fold(0.0, |a: Real, &v| a.max(v.abs()));
        let converged = |k: usize| -> bool {
            let mut r2 = 0.0;
            for a in 0..p {
                let mut acc = 0.0;
                for b in 0..p {
                    acc += b_j[(a, b)] * u[(j * p + b, k)];
                }
                r2 += acc * acc;
            }
            r2.sqrt() <= params.tol * theta_scale
        };
        // Leading converged run (in θ-descending order).
        let mut n_conv = 0;
        while n_conv < dim && converged(order[n_conv]) {
            n_conv += 1;
        }
        let wanted_in_run = match theta_min {
            Some(tmin) => order[..n_conv].iter().filter(|&&k| s[k] >= tmin).count(),
            None => n_conv,
        };
        let done = match (theta_min, want.n_max) {
            (_, Some(nm)) if wanted_in_run >= nm => true,
            // All Ritz values above the cutoff converged, and a block of them below it too.
            (Some(_), _) => wanted_in_run < n_conv && n_conv - wanted_in_run >= p,
            (None, None) => true,
            (None, Some(_)) => false,
        };
        if done || exhausted {
            let whole_space = next.is_none() && n_conv == dim;
            if !done && !whole_space {
                // What convergence still needed: the count asked for, or (a cutoff) every
                // mode below it and a block of p converged beyond it.
                let needed = match (want.n_max, theta_min) {
                    (Some(nm), _) => format!(
                        "{wanted_in_run} of the {nm} modes asked for converged \
                         ({n_conv} Ritz pairs in all)"
                    ),
                    (None, _) => format!(
                        "{n_conv} Ritz pairs converged, {wanted_in_run} of them below the \
                         cutoff; the cutoff is trusted once {p} more converge beyond it"
                    ),
                };
                return Err(ReductionError::LanczosNotConverged {
                    what: what.to_string(),
                    n,
                    dim,
                    needed,
                });
            }
            let keep = want.n_max.map_or(wanted_in_run, |nm| nm.min(wanted_in_run));
            let sel = Mat::<Real>::from_fn(dim, keep, |r, c| u[(r, order[c])]);
            let vectors = basis.q.subcols(0, dim) * &sel;
            let values = (0..keep).map(|c| sigma + 1.0 / s[order[c]]).collect();
            return Ok(Eigenpairs {
                values,
                vectors,
                krylov_dim: dim,
                n_solves,
                solve_s,
                orth_s,
                qr_s,
            });
        }
        push_next(&mut basis, &mut t, next, w, p, m, what)?;
        step += 1;
    }
}

/// Appends the next Lanczos block (or a fresh random block after an invariant subspace) and
/// records the coupling block B_j below the diagonal of T (the block above it is filled from
/// the next step's projection coefficients, then both are averaged).
fn push_next(
    basis: &mut Basis,
    t: &mut Mat<Real>,
    next: Option<(Mat<Real>, Mat<Real>)>,
    w: Mat<Real>,
    p: usize,
    m: &Sparse,
    what: &str,
) -> Result<(), ReductionError> {
    let j = basis.len / p - 1;
    let n = m.nrows();
    match next {
        Some((mw, r)) => {
            for a in 0..p {
                for b in 0..p {
                    t[((j + 1) * p + a, j * p + b)] = r[(a, b)];
                }
            }
            basis.push(w.as_ref(), mw.as_ref());
        }
        None => {
            // Invariant subspace found: continue with a fresh block M-orthogonal to Q.
            let mut r = random_block(n, p, 7 + j as u64);
            basis.project_out(&mut r);
            basis.project_out(&mut r);
            let (mw, _) = chol_qr(&mut r, m)
                .ok_or_else(|| eig_err(what, n, "restart block is degenerate"))?;
            basis.push(r.as_ref(), mw.as_ref());
        }
    }
    Ok(())
}

/// All eigenpairs of the dense symmetric pencil (k, m) with m positive definite: eigenvalues
/// ascending, eigenvectors M-orthonormal (columns). Meant for reduced models (a few thousand DOFs).
pub fn dense_generalized_eigen(
    k: MatRef<'_, Real>,
    m: MatRef<'_, Real>,
) -> Result<(Vec<Real>, Mat<Real>), ReductionError> {
    if k.nrows() != k.ncols() || m.nrows() != k.nrows() || m.ncols() != k.nrows() {
        return Err(ReductionError::ShapeMismatch {
            what: "mass of the pencil".into(),
            rows: m.nrows(),
            cols: m.ncols(),
            expected_rows: k.nrows(),
            expected_cols: k.ncols(),
        });
    }
    dense_all(k, m, "dense pencil")
}
