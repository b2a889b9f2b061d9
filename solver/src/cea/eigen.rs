//! The exact complex eigenvalue analysis: constraint elimination, standard eigenproblem,
//! mode recovery; and the dispatch between the exact and projected methods.

use super::first_order::{first_order_eigen, first_order_matrix_of};
use super::operator::{check_inputs, cholesky};
use super::{
    reduce, CeaError, CeaMatrices, CeaMethod, CeaOptions, CeaResult, CeaStats, Cplx, ModalBasis,
    Mode,
};
use faer::{Mat, MatRef};
use std::time::Instant;

/// `L⁻¹ X L⁻ᵀ` for lower-triangular L.
pub(crate) fn sandwich(l: MatRef<'_, f64>, x: &Mat<f64>) -> Mat<f64> {
    let mut y = x.clone();
    l.solve_lower_triangular_in_place(&mut y);
    let mut z = y.transpose().to_owned();
    l.solve_lower_triangular_in_place(&mut z);
    z.transpose().to_owned()
}

/// Complex eigenvalue analysis about a steady sliding state, without spurious roots.
///
/// Finds the physical roots p of `M ü + (B − C_f) u̇ + K u + (Gᵀ − D) N = 0`, `G u = 0`
/// (solutions `u e^{pt}`). With `opts.method` = `auto` (the default) or `exact`, every
/// root: the constraint is eliminated exactly ([`reduce`]), then the reduced quadratic
/// problem `M_r q̈ + C_r q̇ + K_r q = 0` (size m = n − ng) is brought to a standard one with the
/// Cholesky factor `M_r = L Lᵀ` (`w = Lᵀ q`): `ẅ + Ĉ ẇ + K̂ w = 0`, `Ĉ = L⁻¹C_rL⁻ᵀ`,
/// `K̂ = L⁻¹K_rL⁻ᵀ`, and in first-order form with the state `z = [w; ẇ/σ]`
/// ```text
/// ż = [[0, σ I], [−K̂/σ, −Ĉ]] z,      σ = sqrt(mean |K̂_ii|)
/// ```
/// All 2m eigenvalues come from faer's dense real eigensolver (real Schur; no QZ;
/// eigenvectors only when `compute_shapes`). One root of each complex-conjugate pair is kept
/// (Im p > 0) and every real root; shapes are `u = T L⁻ᵀ w`.
///
/// With `method = projection` (or `auto` above [`super::ProjectionOptions::auto_single_min_dofs`]
/// reduced DOFs with a truncated basis) the roots come from the subspace of the real modes of
/// this same state ([`ModalBasis`]), and every in-band unstable root is then refined exactly by
/// shift-invert Arnoldi on the full first-order operator ([`ModalBasis::solve_refined`],
/// statistics in [`CeaStats::refine`]); in a sweep build the basis once instead
/// ([`super::sweep`]).
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
    match method_for(sys, opts)? {
        CeaMethod::Auto | CeaMethod::Exact => exact(sys, opts),
        CeaMethod::Projection => {
            let basis = ModalBasis::new(sys, opts)?;
            let mut r = basis.solve_refined(sys, opts)?;
            r.stats.time_basis_s = basis.time_s();
            Ok(r)
        }
    }
}

/// The method [`complex_eigen`] runs on `sys`: `opts.method`, with `auto` resolved
/// (projection when the projection is truncated and the reduced problem has more than
/// `projection.auto_single_min_dofs` DOFs, else exact). Never [`CeaMethod::Auto`].
///
/// # Errors
/// The input checks' errors.
pub fn method_for(sys: &CeaMatrices, opts: &CeaOptions) -> Result<CeaMethod, CeaError> {
    let pr = &opts.projection;
    Ok(match opts.method {
        CeaMethod::Auto => {
            let (n, ng) = check_inputs(sys)?;
            if pr.is_truncated() && n - ng > pr.auto_single_min_dofs {
                CeaMethod::Projection
            } else {
                CeaMethod::Exact
            }
        }
        m => m,
    })
}

/// The real first-order matrix whose eigenvalues the exact method computes: the constraint
/// eliminated ([`reduce`]), `M_r = L Lᵀ`, and `A = [[0, σI], [−K̂/σ, −Ĉ]]` (size 2(n − ng),
/// see [`complex_eigen`]); its eigenvalues are the roots p. For cross-checks with other
/// eigensolvers (e.g. `scipy.linalg.eig` on the same matrix).
///
/// # Errors
/// As [`reduce`]; a reduced mass that is not positive definite.
pub fn first_order_matrix(sys: &CeaMatrices, opts: &CeaOptions) -> Result<Mat<f64>, CeaError> {
    let red = reduce(sys, opts)?;
    let llt = cholesky("T^T M T", &red.m_r)?;
    let khat = sandwich(llt.L(), &red.k_r);
    let chat = red.c_r.as_ref().map(|c| sandwich(llt.L(), c));
    Ok(first_order_matrix_of(&khat, chat.as_ref()))
}

/// The exact method.
pub(crate) fn exact(sys: &CeaMatrices, opts: &CeaOptions) -> Result<CeaResult, CeaError> {
    let t0 = Instant::now();
    let red = reduce(sys, opts)?;
    let n = sys.m.nrows();
    let m = red.m_r.nrows();
    let mut stats = CeaStats {
        n,
        n_constraints: n - m,
        n_reduced: m,
        method: CeaMethod::Exact,
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
    let llt = cholesky("T^T M T", &red.m_r)?;
    let l = llt.L();
    let khat = sandwich(l, &red.k_r);
    let chat = red.c_r.as_ref().map(|c| sandwich(l, c));
    let fo = first_order_eigen(&khat, chat.as_ref(), opts.compute_shapes)?;
    let shapes = match &fo.w {
        Some(w) => recover_shapes(w.clone(), Some(l), red.t.as_ref()),
        None => vec![Vec::new(); fo.vals.len()],
    };
    let modes = make_modes(&fo.vals, shapes, fo.rho, opts);
    finish_stats(&mut stats, &modes, fo.rho);
    stats.time_eigen_s = t1.elapsed().as_secs_f64();
    Ok(CeaResult { modes, stats })
}

/// Modes from the kept eigenvalues and their shapes, sorted by frequency then real part.
pub(crate) fn make_modes(
    vals: &[Cplx],
    shapes: Vec<Vec<Cplx>>,
    rho: f64,
    opts: &CeaOptions,
) -> Vec<Mode> {
    let tol = opts.unstable_tol * rho;
    let mut modes: Vec<Mode> = vals
        .iter()
        .zip(shapes)
        .map(|(&p, shape)| Mode {
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
        })
        .collect();
    modes.sort_by(|x, y| {
        x.frequency_hz
            .total_cmp(&y.frequency_hz)
            .then(x.real_part.total_cmp(&y.real_part))
    });
    modes
}

/// Mode counts, largest real part and spectral radius.
pub(crate) fn finish_stats(stats: &mut CeaStats, modes: &[Mode], rho: f64) {
    stats.n_modes = modes.len();
    stats.n_real_roots = modes.iter().filter(|x| x.eigenvalue.im == 0.0).count();
    stats.n_unstable = modes.iter().filter(|x| x.unstable).count();
    stats.max_real_part = modes
        .iter()
        .map(|x| x.real_part)
        .fold(f64::NEG_INFINITY, f64::max);
    stats.spectral_radius = rho;
}

/// `u = T L⁻ᵀ w` for `w = [Re W | Im W]` (m × 2k), each shape normalised to unit 2-norm with
/// its largest entry real positive. `l = None` is L = I, `t = None` is T = I.
pub(crate) fn recover_shapes(
    mut w: Mat<f64>,
    l: Option<MatRef<'_, f64>>,
    t: Option<&Mat<f64>>,
) -> Vec<Vec<Cplx>> {
    let k = w.ncols() / 2;
    if let Some(l) = l {
        l.transpose().solve_upper_triangular_in_place(&mut w);
    }
    let q = match t {
        Some(t) => t * &w,
        None => w,
    };
    let n = q.nrows();
    (0..k)
        .map(|c| {
            normalise_shape(
                (0..n)
                    .map(|i| Cplx::new(q[(i, c)], q[(i, c + k)]))
                    .collect(),
            )
        })
        .collect()
}

/// A shape scaled to unit 2-norm with its largest entry real positive (zero stays zero).
pub(crate) fn normalise_shape(mut v: Vec<Cplx>) -> Vec<Cplx> {
    let n = v.len();
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
}
