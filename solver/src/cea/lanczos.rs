//! Partial symmetric eigensolve of the constrained problem for the projection basis:
//! shift-invert Krylov (Lanczos with full reorthogonalisation and explicit Rayleigh–Ritz) on the
//! bordered matrix, with the mode count below the cutoff from Sylvester's law of inertia.

use super::operator::pivot_ratio;
use super::CeaError;
use faer::linalg::solvers::{Lblt, Solve};
use faer::{Col, Mat, Side};

/// The lowest modes of `Ks φ = λ M φ`, `G φ = 0` (Ks symmetric, M SPD), λ below a cutoff.
pub(crate) struct LowModes {
    /// Eigenvalues λ, ascending.
    pub(crate) lambda: Vec<f64>,
    /// Eigenvectors (n × nb): `G Φ = 0`, `Φᵀ M Φ = I`.
    pub(crate) phi: Mat<f64>,
}

/// `[Ks − s M, c Gᵀ; c G, 0]` (c scales G to the size of the stiffness block; the inertia and
/// the displacement part of a solution do not depend on it).
fn bordered(ks: &Mat<f64>, m: &Mat<f64>, g: Option<&Mat<f64>>, s: f64) -> Mat<f64> {
    let n = ks.nrows();
    let ng = g.map_or(0, |g| g.nrows());
    let amax = |a: &Mat<f64>| {
        let mut x = 0.0f64;
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                x = x.max(a[(i, j)].abs());
            }
        }
        x
    };
    let scale = match g {
        Some(g) if ng > 0 => {
            let gm = amax(g);
            if gm > 0.0 {
                (amax(ks) + s.abs() * amax(m)) / gm
            } else {
                1.0
            }
        }
        _ => 1.0,
    };
    Mat::from_fn(n + ng, n + ng, |i, j| match (i < n, j < n) {
        (true, true) => ks[(i, j)] - s * m[(i, j)],
        (true, false) => scale * g.map_or(0.0, |g| g[(j - n, i)]),
        (false, true) => scale * g.map_or(0.0, |g| g[(i - n, j)]),
        (false, false) => 0.0,
    })
}

/// Number of negative eigenvalues of the symmetric matrix factored as `P L B Lᵀ Pᵀ`, and the
/// smallest |pivot| over the largest (1 × 1 and 2 × 2 blocks of B).
fn inertia(f: &Lblt<f64>) -> (usize, f64) {
    let (d, e) = (f.B_diag(), f.B_subdiag());
    let n = d.dim();
    let (mut neg, mut i) = (0, 0);
    let (mut pmin, mut pmax) = (f64::INFINITY, 0.0f64);
    while i < n {
        if i + 1 < n && e[i] != 0.0 {
            let (a, b, c) = (d[i], e[i], d[i + 1]);
            let det = a * c - b * b;
            neg += if det < 0.0 {
                1
            } else if a + c < 0.0 {
                2
            } else {
                0
            };
            let (tr, disc) = (0.5 * (a + c), (0.25 * (a - c) * (a - c) + b * b).sqrt());
            pmin = pmin.min((tr.abs() - disc).abs());
            pmax = pmax.max(tr.abs() + disc);
            i += 2;
        } else {
            neg += usize::from(d[i] < 0.0);
            pmin = pmin.min(d[i].abs());
            pmax = pmax.max(d[i].abs());
            i += 1;
        }
    }
    (neg, if pmax > 0.0 { pmin / pmax } else { 0.0 })
}

/// Number of eigenvalues of the constrained problem below `s` (inertia of the bordered matrix
/// minus ng), and the pivot ratio of the factor.
fn count_below(ks: &Mat<f64>, m: &Mat<f64>, g: Option<&Mat<f64>>, s: f64) -> (usize, f64) {
    let ng = g.map_or(0, |g| g.nrows());
    let f = bordered(ks, m, g, s).lblt(Side::Lower);
    let (neg, ratio) = inertia(&f);
    (neg.saturating_sub(ng), ratio)
}

/// The modes of `Ks φ = λ M φ`, `G φ = 0` with λ < `lambda_c`, or `None` when this method
/// should not be used (none below the cutoff, more than `max_modes`, or no convergence within
/// `max_dim` vectors): the caller then runs the dense eigensolver.
///
/// # Method
/// 1. *Count.* `Z(s) = [Ks − sM, Gᵀ; G, 0]` is congruent to `diag(Tᵀ(Ks − sM)T, W)` with W of
///    inertia (ng, ng, 0) (T a basis of null(G), G of full row rank), so the number of
///    constrained eigenvalues below s is the number of negative eigenvalues of Z(s) minus ng
///    (Sylvester), read from a Bunch–Kaufman `LBLᵀ` of Z(λ_c).
/// 2. *Shift-invert.* With σ = −λ_c/100, `S x = y` where `Z(σ)[y; μ] = [M x; 0]` is
///    self-adjoint in the M inner product on null(G) with eigenvalues θ = 1/(λ − σ): the wanted
///    modes are the largest θ. The Krylov vectors of S are M-orthonormalised twice against all
///    previous ones; `H = Qᵀ M S Q` is formed explicitly (so a new random vector can be added
///    when a multiple eigenvalue leaves the Krylov space short) and its eigenpairs are the Ritz
///    pairs; a pair is converged when `‖S y − θ y‖_M ≤ tol·|θ|` (y M-normalised).
/// 3. The iteration stops when the Ritz values below λ_c are as many as the count (Cauchy
///    interlacing: never more, so none is missing) and those up to λ_c/4 have converged; the
///    basis is then the Ritz vectors of those below λ_c. `None` after `3 count + 150` vectors.
pub(crate) fn lowest_modes(
    ks: &Mat<f64>,
    m: &Mat<f64>,
    g: Option<&Mat<f64>>,
    lambda_c: f64,
    max_modes: usize,
    tol: f64,
    interrupt: &crate::Interrupt,
) -> Result<Option<LowModes>, CeaError> {
    let n = m.nrows();
    if !(lambda_c > 0.0 && lambda_c.is_finite()) {
        return Ok(None);
    }
    let (count, ratio_c) = count_below(ks, m, g, lambda_c);
    if count == 0 || count > max_modes || ratio_c.is_nan() {
        return Ok(None);
    }
    let ng = g.map_or(0, |g| g.nrows());
    let mut sigma = -0.01 * lambda_c;
    let mut f = bordered(ks, m, g, sigma).partial_piv_lu();
    for _ in 0..4 {
        if pivot_ratio(f.U(), |x: &f64| x.abs()) > 1e-13 {
            break;
        }
        sigma *= 3.0;
        f = bordered(ks, m, g, sigma).partial_piv_lu();
    }
    if pivot_ratio(f.U(), |x: &f64| x.abs()) <= 1e-13 {
        return Ok(None);
    }
    let apply = |mx: &Col<f64>| -> Col<f64> {
        let mut rhs = Col::<f64>::from_fn(n + ng, |i| if i < n { mx[i] } else { 0.0 });
        f.solve_in_place(rhs.as_mat_mut());
        Col::from_fn(n, |i| rhs[i])
    };
    let max_dim = (3 * count + 150).min(n.saturating_sub(ng)).max(count + 1);
    let mut q = Mat::<f64>::zeros(n, max_dim);
    let mut mq = Mat::<f64>::zeros(n, max_dim);
    let mut w_all = Mat::<f64>::zeros(n, max_dim);
    let mut mw_all = Mat::<f64>::zeros(n, max_dim);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut dim = 0;
    let mut last_converged = 0;
    let mut next_check = count.max(10);
    // Orthogonalises (w, Mw) against the first `dim` vectors, twice; returns ‖w‖_M.
    let orth = |w: &mut Col<f64>, mw: &mut Col<f64>, q: &Mat<f64>, mq: &Mat<f64>, dim: usize| {
        for _ in 0..2 {
            if dim > 0 {
                let c = mq.subcols(0, dim).transpose() * &*w;
                *w -= q.subcols(0, dim) * &c;
            }
        }
        // M w afresh: updating it with the same combinations loses accuracy when w was
        // mostly in span(Q) (M is ill-conditioned in mixed physical/modal coordinates).
        *mw = m * &*w;
        let nn = (w.transpose() * &*mw).max(0.0);
        nn.sqrt()
    };
    let mut pending: Option<(Col<f64>, Col<f64>)> = None;
    while dim < max_dim {
        super::options::check_interrupt(interrupt, "the projection basis' Lanczos")?;
        // The next (unnormalised) vector and its M product.
        let (mut w, mut mw) = match pending.take() {
            Some(x) => x,
            None => {
                let x = Col::<f64>::from_fn(n, |_| rnd());
                let y = apply(&(m * &x));
                let my = m * &y;
                (y, my)
            }
        };
        let beta = orth(&mut w, &mut mw, &q, &mq, dim);
        let wn = (w.transpose() * &mw).abs().sqrt();
        if !beta.is_finite() {
            return Ok(None);
        }
        if beta <= 1e-10 * wn.max(f64::MIN_POSITIVE) {
            // w lies in span(Q): start again from a random vector.
            continue;
        }
        q.col_mut(dim).copy_from(&w / beta);
        mq.col_mut(dim).copy_from(&mw / beta);
        // S q_dim and its M product (H's column and the next Krylov vector).
        let sw = apply(&mq.col(dim).to_owned());
        let msw = m * &sw;
        w_all.col_mut(dim).copy_from(&sw);
        mw_all.col_mut(dim).copy_from(&msw);
        dim += 1;
        pending = Some((sw, msw));
        if dim < next_check && dim < max_dim {
            continue;
        }
        next_check = dim + 10;
        // Rayleigh–Ritz on H = Qᵀ M S Q (symmetrised).
        let h = mq.subcols(0, dim).transpose() * w_all.subcols(0, dim);
        let hs = Mat::from_fn(dim, dim, |i, j| 0.5 * (h[(i, j)] + h[(j, i)]));
        let evd = hs
            .self_adjoint_eigen(Side::Lower)
            .map_err(|_| CeaError::NoConvergence {
                what: "Rayleigh-Ritz eigendecomposition (projection basis)",
                n: dim,
            })?;
        let (th, s) = (evd.S().column_vector(), evd.U());
        // Wanted: θ > 0 with λ = σ + 1/θ ≤ λ_c, or θ < 0 (λ < σ).
        let wanted: Vec<usize> = (0..dim)
            .filter(|&i| {
                let t = th[i];
                t != 0.0 && (t < 0.0 || sigma + 1.0 / t <= lambda_c * (1.0 + 1e-9))
            })
            .collect();
        let sw_ = Mat::from_fn(dim, wanted.len(), |r, c| s[(r, wanted[c])]);
        let ws = w_all.subcols(0, dim) * &sw_;
        let mws = mw_all.subcols(0, dim) * &sw_;
        let qs = q.subcols(0, dim) * &sw_;
        let mqs = mq.subcols(0, dim) * &sw_;
        // Done when every eigenvalue below λ_c has its Ritz value (by Cauchy interlacing the
        // Ritz values below λ_c are never more than the eigenvalues there, so equal counts
        // mean none is missing) and the pairs up to λ_c/4 (half the cutoff frequency, where
        // the band lies) have converged; the few near λ_c converge slowly and only enlarge
        // the subspace (the roots that matter are refined exactly afterwards).
        let mut conv = 0;
        let mut all_low = true;
        for (c, &i) in wanted.iter().enumerate() {
            let t = th[i];
            let r = ws.col(c) - qs.col(c) * t;
            let mr = mws.col(c) - mqs.col(c) * t;
            let res = (r.transpose() * &mr).abs().sqrt();
            if res <= tol * t.abs() {
                conv += 1;
            } else if sigma + 1.0 / t <= 0.25 * lambda_c {
                all_low = false;
            }
        }
        if wanted.len() == count && all_low {
            let mut order: Vec<(f64, usize)> = wanted
                .iter()
                .enumerate()
                .map(|(c, &i)| (sigma + 1.0 / th[i], c))
                .collect();
            order.sort_by(|a, b| a.0.total_cmp(&b.0));
            let phi = Mat::from_fn(n, count, |r, k| qs[(r, order[k].1)]);
            let Some(phi) = clean(phi, m, g) else {
                return Ok(None);
            };
            return Ok(Some(LowModes {
                lambda: order.iter().map(|x| x.0).collect(),
                phi,
            }));
        }
        if conv <= last_converged && dim > count + 30 {
            // No progress: a multiple eigenvalue may be missing from the Krylov space.
            pending = None;
        }
        last_converged = conv;
    }
    Ok(None)
}

/// Φ projected exactly on null(G) (`Φ − Gᵀ(GGᵀ)⁻¹GΦ`: the bordered solves leave `GΦ` at the
/// solver's round-off, ~1e-10 relative) and M-orthonormalised again (`Φ L⁻ᵀ`, `ΦᵀMΦ = LLᵀ`).
/// `None` when a Cholesky factorisation fails.
fn clean(mut phi: Mat<f64>, m: &Mat<f64>, g: Option<&Mat<f64>>) -> Option<Mat<f64>> {
    if let Some(g) = g.filter(|g| g.nrows() > 0) {
        let ggt = g * g.transpose();
        let mut c = g * &phi;
        ggt.llt(Side::Lower).ok()?.solve_in_place(&mut c);
        phi -= g.transpose() * &c;
    }
    let gram = phi.transpose() * (m * &phi);
    let llt = gram.llt(Side::Lower).ok()?;
    let mut t = phi.transpose().to_owned();
    llt.L().solve_lower_triangular_in_place(&mut t);
    Some(t.transpose().to_owned())
}
