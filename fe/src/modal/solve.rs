//! Entry point of the modal solve.

use super::dense::dense_eigen;
use super::factor::factorise;
use super::lanczos::{lanczos, Want};
use super::options::{FactorKind, ModalOptions, ModalStats, ModalStatus, Modes};
use super::spmm::sym_matmul;
use crate::ordering::{nested_dissection, FillOrdering, AUTO_ND_MIN_DOFS};
use crate::{FeError, Real};
use faer::sparse::{SparseColMat, SparseColMatRef};
use faer::Mat;
use std::f64::consts::PI;
use std::time::Instant;

/// Lowest modes of K φ = ω² M φ (K, M symmetric with full storage, M positive definite).
///
/// Shift-invert block Lanczos on (K − σM)⁻¹M in the M-inner product with σ < 0, full
/// reorthogonalisation and thick restart; one sparse Cholesky of K − σM. Problems with at most
/// `opts.dense_below` DOFs are solved densely. Returned eigenvalues are Rayleigh quotients of
/// the M-normalised Ritz vectors; frequencies are sign(ω²)·sqrt|ω²|/2π.
///
/// Errors: invalid options, dimension mismatch, `n_modes` > n, non-finite entries, failed
/// factorisation. Non-convergence within `max_restarts` is `Ok` with
/// `ModalStatus::MaxIterations`.
///
/// Without DOF coordinates, `opts.ordering = auto` means AMD; see [`solve_modes_with`].
pub fn solve_modes(
    k: &SparseColMat<usize, Real>,
    m: &SparseColMat<usize, Real>,
    opts: &ModalOptions,
) -> Result<Modes, FeError> {
    solve_modes_with(k, m, opts, None)
}

/// [`solve_modes`] with the coordinates of every DOF (`dof_coords[i]` = point of the node of
/// DOF i, e.g. from [`dof_coordinates`](crate::ordering::dof_coordinates)), which enable the
/// nested-dissection ordering (`opts.ordering = nested_dissection`, or `auto` for n ≥ 20 000).
///
/// Errors as [`solve_modes`], plus `dof_coords` of the wrong length, non-finite coordinates,
/// and `ordering = nested_dissection` without coordinates.
pub fn solve_modes_with(
    k: &SparseColMat<usize, Real>,
    m: &SparseColMat<usize, Real>,
    opts: &ModalOptions,
    dof_coords: Option<&[[Real; 3]]>,
) -> Result<Modes, FeError> {
    let t0 = Instant::now();
    opts.validate()?;
    let n = k.nrows();
    for (what, got) in [
        ("K columns", k.ncols()),
        ("M rows", m.nrows()),
        ("M columns", m.ncols()),
    ] {
        if got != n {
            return Err(FeError::Dimension {
                what,
                got,
                expected: n,
            });
        }
    }
    if n == 0 {
        return Err(FeError::Dimension {
            what: "free DOFs",
            got: 0,
            expected: 1,
        });
    }
    if let Some(req) = opts.n_modes {
        if req > n {
            return Err(FeError::TooManyModes { requested: req, n });
        }
    }
    if let Some(c) = dof_coords {
        if c.len() != n {
            return Err(FeError::Dimension {
                what: "DOF coordinates",
                got: c.len(),
                expected: n,
            });
        }
    }
    let use_nd = match opts.ordering {
        FillOrdering::Amd => false,
        FillOrdering::Auto => dof_coords.is_some() && n >= AUTO_ND_MIN_DOFS,
        FillOrdering::NestedDissection if dof_coords.is_none() => {
            return Err(FeError::Dimension {
                what: "DOF coordinates (modal.ordering = nested_dissection needs them)",
                got: 0,
                expected: n,
            })
        }
        FillOrdering::NestedDissection => true,
    };
    for (what, a) in [("K", k), ("M", m)] {
        if a.val().iter().any(|v| !v.is_finite()) {
            return Err(FeError::NonFinite {
                what: what.to_string(),
            });
        }
    }
    let (k, m) = (k.as_ref(), m.as_ref());
    let sigma = match opts.shift_hz {
        Some(f) => -(2.0 * PI * f).powi(2),
        None => auto_shift(k, m),
    };
    let lambda_cut = opts.max_frequency_hz.map(|f| (2.0 * PI * f).powi(2));
    let b = opts.block_size.min(n);
    let nev = opts.n_modes.unwrap_or(2 * b);
    let mut mmax = if opts.max_basis > 0 {
        opts.max_basis
    } else {
        (2 * nev).max(nev + 4 * b)
    };
    mmax = mmax.div_ceil(b) * b;
    let mut stats = ModalStats {
        n,
        shift: sigma,
        factor_kind: FactorKind::Dense,
        fallback_reason: None,
        ordering: None,
        nested_dissection: None,
        factor_nnz: 0,
        supernodal: false,
        factor_flops: 0.0,
        iterations: 0,
        restarts: 0,
        factorisations: 0,
        matvecs: 0,
        m_products: 0,
        block_size: b,
        max_basis: 0,
        factor_s: 0.0,
        ordering_s: 0.0,
        lanczos_s: 0.0,
        solve_s: 0.0,
        split: None,
        orth_s: 0.0,
        ritz_s: 0.0,
        qr_fallbacks: 0,
        post_s: 0.0,
        total_s: 0.0,
        max_residual: 0.0,
    };

    let (x, status) = if n <= opts.dense_below || mmax + 2 * b > n {
        let t1 = Instant::now();
        let (lam, phi) = dense_eigen(k, m)?;
        stats.lanczos_s = t1.elapsed().as_secs_f64();
        let mut count = opts.n_modes.unwrap_or(n).min(n);
        if let Some(cut) = lambda_cut {
            count = lam[..count].iter().filter(|&&l| l <= cut).count();
        }
        (
            phi.as_ref().subcols(0, count).to_owned(),
            ModalStatus::Converged,
        )
    } else {
        let t1 = Instant::now();
        let mut split = None;
        let perm = match (use_nd, dof_coords) {
            (true, Some(c)) => {
                let (p, nd) = nested_dissection(k.symbolic(), c, &opts.nested_dissection)?;
                stats.ordering_s = nd.ordering_s;
                if opts.split_factor && nd.top_split_dofs[0] > 0 && nd.top_split_dofs[1] > 0 {
                    split = Some(nd.top_split_dofs);
                }
                stats.nested_dissection = Some(nd);
                Some(p)
            }
            _ => None,
        };
        if opts.interrupt.is_set() {
            return Err(FeError::Interrupted {
                during: "the modal solve's factorisation",
            });
        }
        let f = factorise(k, m, sigma, perm.as_ref(), split)?;
        stats.split = f.split.clone();
        drop(perm);
        stats.factor_s = t1.elapsed().as_secs_f64();
        stats.factor_kind = f.kind;
        stats.supernodal = f.supernodal;
        stats.factor_flops = f.factor_flops;
        if f.kind != FactorKind::Lu {
            stats.ordering = Some(if use_nd {
                FillOrdering::NestedDissection
            } else {
                FillOrdering::Amd
            });
        }
        stats.fallback_reason = f.fallback_reason;
        stats.factor_nnz = f.factor_nnz;
        stats.factorisations = f.factorisations;
        let t2 = Instant::now();
        let want = Want {
            n_modes: opts.n_modes,
            theta_min: lambda_cut.map(|c| 1.0 / (c - sigma)),
        };
        let out = lanczos(
            &f.factor,
            m,
            &want,
            b,
            mmax,
            opts.tol,
            opts.max_restarts,
            opts.seed,
            &opts.interrupt,
        )?;
        stats.lanczos_s = t2.elapsed().as_secs_f64();
        stats.iterations = out.iterations;
        stats.restarts = out.restarts;
        stats.matvecs = out.solves;
        stats.m_products = out.m_products;
        stats.max_basis = out.max_basis;
        stats.solve_s = out.solve_s;
        stats.orth_s = out.orth_s;
        stats.ritz_s = out.ritz_s;
        stats.qr_fallbacks = out.qr_fallbacks;
        let status = if out.done {
            ModalStatus::Converged
        } else {
            ModalStatus::MaxIterations {
                converged: out.converged,
            }
        };
        (out.x, status)
    };

    // Rayleigh quotients, M-normalisation and explicit residuals.
    let t_post = Instant::now();
    let nm = x.ncols();
    let mut kx = Mat::<Real>::zeros(n, nm);
    let mut mx = Mat::<Real>::zeros(n, nm);
    sym_matmul(k, x.as_ref(), kx.as_mut());
    sym_matmul(m, x.as_ref(), mx.as_mut());
    let mut modes: Vec<(Real, usize, Real)> = Vec::with_capacity(nm);
    for j in 0..nm {
        let (xs, ks, ms) = (x.col_as_slice(j), kx.col_as_slice(j), mx.col_as_slice(j));
        let xmx: Real = xs.iter().zip(ms).map(|(a, b)| a * b).sum();
        let xkx: Real = xs.iter().zip(ks).map(|(a, b)| a * b).sum();
        if xmx.is_nan() || xmx <= 0.0 || !xkx.is_finite() {
            return Err(FeError::NonFinite {
                what: format!("Ritz vector {j} (x'Mx = {xmx:e})"),
            });
        }
        let lam = xkx / xmx;
        let (mut r2, mut k2, mut m2) = (0.0, 0.0, 0.0);
        for t in 0..n {
            let r = ks[t] - lam * ms[t];
            r2 += r * r;
            k2 += ks[t] * ks[t];
            m2 += ms[t] * ms[t];
        }
        let res = r2.sqrt()
            / k2.sqrt()
                .max(sigma.abs() * m2.sqrt())
                .max(Real::MIN_POSITIVE);
        modes.push((lam, j, res / 1.0));
        let _ = xmx;
    }
    modes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut shapes = Mat::<Real>::zeros(n, nm);
    let mut eigenvalues = Vec::with_capacity(nm);
    for (c, &(lam, j, res)) in modes.iter().enumerate() {
        let xs = x.col_as_slice(j);
        let ms = mx.col_as_slice(j);
        let s = xs.iter().zip(ms).map(|(a, b)| a * b).sum::<Real>().sqrt();
        for t in 0..n {
            shapes[(t, c)] = xs[t] / s;
        }
        eigenvalues.push(lam);
        stats.max_residual = stats.max_residual.max(res);
    }
    let frequencies_hz = eigenvalues
        .iter()
        .map(|&l: &Real| l.signum() * l.abs().sqrt() / (2.0 * PI))
        .collect();
    stats.post_s = t_post.elapsed().as_secs_f64();
    stats.total_s = t0.elapsed().as_secs_f64();
    Ok(Modes {
        frequencies_hz,
        eigenvalues,
        shapes,
        stats,
        status,
    })
}

/// σ = −1e-8 · median(K_ii / M_ii): far below the first elastic eigenvalue of typical
/// structural meshes, yet K − σM stays well-conditioned when rigid modes exist.
fn auto_shift(k: SparseColMatRef<'_, usize, Real>, m: SparseColMatRef<'_, usize, Real>) -> Real {
    let diag = |a: SparseColMatRef<'_, usize, Real>, j: usize| {
        let rows = a.row_idx_of_col_raw(j);
        rows.binary_search(&j)
            .map(|p| a.val_of_col(j)[p])
            .unwrap_or(0.0)
    };
    let mut r: Vec<Real> = (0..k.ncols())
        .map(|j| diag(k, j) / diag(m, j))
        .filter(|v| v.is_finite() && *v > 0.0)
        .collect();
    if r.is_empty() {
        return -1.0;
    }
    let mid = r.len() / 2;
    let (_, med, _) = r.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
    -1e-8 * *med
}
