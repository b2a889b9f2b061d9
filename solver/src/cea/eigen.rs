//! First-order form, standard eigenproblem, and mode recovery.

use super::{reduce, CeaError, CeaMatrices, CeaOptions, CeaResult, CeaStats, Cplx, Mode};
use faer::{Mat, Side};
use std::time::Instant;

/// `L⁻¹ X L⁻ᵀ` for lower-triangular L.
fn sandwich(l: faer::MatRef<'_, f64>, x: &Mat<f64>) -> Mat<f64> {
    let mut y = x.clone();
    l.solve_lower_triangular_in_place(&mut y);
    let mut z = y.transpose().to_owned();
    l.solve_lower_triangular_in_place(&mut z);
    z.transpose().to_owned()
}

/// Complex eigenvalue analysis about a steady sliding state, without spurious roots.
///
/// Finds every physical root p of `M ü + (B − C_f) u̇ + K u + (Gᵀ − D) N = 0`, `G u = 0`
/// (solutions `u e^{pt}`): the constraint is eliminated exactly ([`reduce`]), then the reduced quadratic
/// problem `M_r q̈ + C_r q̇ + K_r q = 0` (size m = n − ng) is brought to a standard one with the
/// Cholesky factor `M_r = L Lᵀ` (`w = Lᵀ q`): `ẅ + Ĉ ẇ + K̂ w = 0`, `Ĉ = L⁻¹C_rL⁻ᵀ`,
/// `K̂ = L⁻¹K_rL⁻ᵀ`, and in first-order form with the state `z = [w; ẇ/σ]`
/// ```text
/// ż = [[0, σ I], [−K̂/σ, −Ĉ]] z,      σ = sqrt(mean |K̂_ii|)
/// ```
/// (σ balances the two blocks so that the matrix norm is ~ max|p| rather than max|p|²).
/// All 2m eigenvalues come from faer's dense `eigen()` (real Schur; no QZ). One root of each
/// complex-conjugate pair is kept (Im p > 0) and every real root; shapes are `u = T L⁻ᵀ w`.
///
/// # Reference
/// $$(p^2[M_{dd}] + p[B_{dd}] + [K_{dd}])\{\psi\} = 0$$ [Paper eqs. (19)–(24)], reduced as
/// derived in [`reduce`]. ζ = −2 Re p/|Im p| as in DESIGN.md.
///
/// # Errors
/// See [`reduce`]; also a reduced mass that is not positive definite and non-convergence
/// of the eigenvalue solver.
pub fn complex_eigen(sys: &CeaMatrices, opts: &CeaOptions) -> Result<CeaResult, CeaError> {
    opts.validate()?;
    let t0 = Instant::now();
    let red = reduce(sys, opts)?;
    let n = sys.m.nrows();
    let m = red.m_r.nrows();
    let mut stats = CeaStats {
        n,
        n_constraints: n - m,
        n_reduced: m,
        constraint_rank_ratio: red.rank_ratio,
        time_reduce_s: t0.elapsed().as_secs_f64(),
        ..CeaStats::default()
    };
    let t1 = Instant::now();
    if m == 0 {
        return Ok(CeaResult {
            modes: Vec::new(),
            stats,
        });
    }
    let llt = red.m_r.llt(Side::Lower).map_err(|e| match e {
        faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
            CeaError::NotPositiveDefinite {
                what: "T^T M T",
                n: m,
                pivot: index,
            }
        }
    })?;
    let l = llt.L();
    let khat = sandwich(l, &red.k_r);
    let chat = red.c_r.as_ref().map(|c| sandwich(l, c));
    let mean_k = (0..m).map(|i| khat[(i, i)].abs()).sum::<f64>() / m as f64;
    let sigma = if mean_k > 0.0 && mean_k.is_finite() {
        mean_k.sqrt()
    } else {
        1.0
    };
    let a = Mat::from_fn(2 * m, 2 * m, |i, j| match (i < m, j < m) {
        (true, true) => 0.0,
        (true, false) => {
            if j - m == i {
                sigma
            } else {
                0.0
            }
        }
        (false, true) => -khat[(i - m, j)] / sigma,
        (false, false) => chat.as_ref().map_or(0.0, |c| -c[(i - m, j - m)]),
    });
    let (vals, vecs): (Vec<Cplx>, Option<Mat<Cplx>>) = if opts.compute_shapes {
        let e = a.eigen().map_err(|_| CeaError::NoConvergence {
            what: "eigendecomposition",
            n: 2 * m,
        })?;
        let s = e.S().column_vector();
        let vals = (0..2 * m).map(|i| s[i]).collect();
        (vals, Some(e.U().to_owned()))
    } else {
        let v = a.eigenvalues().map_err(|_| CeaError::NoConvergence {
            what: "eigenvalues",
            n: 2 * m,
        })?;
        (v, None)
    };
    let rho = vals.iter().map(|p| p.norm()).fold(0.0, f64::max);
    let keep: Vec<usize> = (0..2 * m).filter(|&j| vals[j].im >= 0.0).collect();
    for (j, p) in vals.iter().enumerate() {
        if !(p.re.is_finite() && p.im.is_finite()) {
            return Err(CeaError::NonFinite {
                what: "eigenvalue",
                row: j,
                col: 0,
                value: if p.re.is_finite() { p.im } else { p.re },
            });
        }
    }
    let shapes = match &vecs {
        Some(u) => recover_shapes(u, &keep, m, l, red.t.as_ref()),
        None => vec![Vec::new(); keep.len()],
    };
    let tol = opts.unstable_tol * rho;
    let mut modes: Vec<Mode> = keep
        .iter()
        .zip(shapes)
        .map(|(&j, shape)| {
            let p = vals[j];
            Mode {
                eigenvalue: p,
                frequency_hz: p.im.abs() / (2.0 * std::f64::consts::PI),
                real_part: p.re,
                damping_ratio: if p.im == 0.0 {
                    None
                } else {
                    Some(-2.0 * p.re / p.im.abs())
                },
                unstable: p.re > tol,
                shape,
            }
        })
        .collect();
    modes.sort_by(|x, y| {
        x.frequency_hz
            .total_cmp(&y.frequency_hz)
            .then(x.real_part.total_cmp(&y.real_part))
    });
    stats.n_modes = modes.len();
    stats.n_real_roots = modes.iter().filter(|x| x.eigenvalue.im == 0.0).count();
    stats.n_unstable = modes.iter().filter(|x| x.unstable).count();
    stats.max_real_part = modes
        .iter()
        .map(|x| x.real_part)
        .fold(f64::NEG_INFINITY, f64::max);
    stats.spectral_radius = rho;
    stats.time_eigen_s = t1.elapsed().as_secs_f64();
    Ok(CeaResult { modes, stats })
}

/// u = T L⁻ᵀ w for the kept eigenvectors (w = top half of the state vector), normalised to
/// unit 2-norm with the largest entry real positive.
fn recover_shapes(
    u: &Mat<Cplx>,
    keep: &[usize],
    m: usize,
    l: faer::MatRef<'_, f64>,
    t: Option<&Mat<f64>>,
) -> Vec<Vec<Cplx>> {
    let k = keep.len();
    // [Re W | Im W] (m × 2k), solve Lᵀ Q = W.
    let mut w = Mat::from_fn(m, 2 * k, |i, c| {
        if c < k {
            u[(i, keep[c])].re
        } else {
            u[(i, keep[c - k])].im
        }
    });
    l.transpose().solve_upper_triangular_in_place(&mut w);
    let q = match t {
        Some(t) => t * &w,
        None => w,
    };
    let n = q.nrows();
    (0..k)
        .map(|c| {
            let mut v: Vec<Cplx> = (0..n)
                .map(|i| Cplx::new(q[(i, c)], q[(i, c + k)]))
                .collect();
            let norm = v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
            let imax = (0..n)
                .max_by(|&a, &b| v[a].norm_sqr().total_cmp(&v[b].norm_sqr()))
                .unwrap_or(0);
            if norm > 0.0 && n > 0 {
                let phase = v[imax].conj() / v[imax].norm();
                for z in &mut v {
                    *z = *z * phase / norm;
                }
            }
            v
        })
        .collect()
}
