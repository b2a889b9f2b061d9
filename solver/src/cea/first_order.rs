//! The standard eigenproblem of `ẅ + Ĉ ẇ + K̂ w = 0` in first-order form.

use super::{CeaError, Cplx};
use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{evd_real, evd_scratch, ComputeEigenvectors};
use faer::Mat;

/// A kept root: eigenvalue, column of Re u, (column of Im u, its sign) for a complex root.
type Kept = (Cplx, usize, Option<(usize, f64)>);

/// Size of the first-order problem below which the dense eigensolver runs sequentially.
const SEQ_BELOW: usize = 512;

/// Roots of `ẅ + Ĉ ẇ + K̂ w = 0` (identity mass), one per conjugate pair.
pub(crate) struct FirstOrder {
    /// Kept eigenvalues p (Im p ≥ 0: one of each conjugate pair and every real root).
    pub(crate) vals: Vec<Cplx>,
    /// Largest |p| over all 2m roots.
    pub(crate) rho: f64,
    /// `[Re W | Im W]` (m × 2k): the w-part of the kept eigenvectors (column c of `W` belongs
    /// to `vals[c]`); `None` when vectors were not asked for.
    pub(crate) w: Option<Mat<f64>>,
}

/// Solves `ż = A z`, `A = [[0, σI], [−K̂/σ, −Ĉ]]`, `z = [w; ẇ/σ]`, `σ = sqrt(mean |K̂_ii|)`
/// (σ balances the blocks so that ‖A‖ ~ max|p| rather than max|p|²), by faer's dense real
/// `evd_real` (Hessenberg + real Schur; no QZ). Right eigenvectors are computed only when
/// `vectors`; only the w-half of the kept ones is returned, without forming the complex
/// 2m × 2m eigenvector matrix.
///
/// # Errors
/// Non-convergence of the eigenvalue solver and non-finite eigenvalues.
pub(crate) fn first_order_eigen(
    khat: &Mat<f64>,
    chat: Option<&Mat<f64>>,
    vectors: bool,
) -> Result<FirstOrder, CeaError> {
    let m = khat.nrows();
    let n2 = 2 * m;
    let a = first_order_matrix_of(khat, chat);
    let (s_re, s_im, u, rho) = real_evd(&a, vectors)?;
    // (eigenvalue, column of Re, column of Im and its sign) of the kept roots.
    let mut kept: Vec<Kept> = Vec::with_capacity(m + 1);
    let mut j = 0;
    while j < n2 {
        if s_im[j] == 0.0 {
            kept.push((Cplx::new(s_re[j], 0.0), j, None));
            j += 1;
        } else {
            // A pair: columns j, j+1 hold Re and Im of the vector of s_re[j] + i s_im[j].
            let sign = if s_im[j] > 0.0 { 1.0 } else { -1.0 };
            kept.push((Cplx::new(s_re[j], s_im[j].abs()), j, Some((j + 1, sign))));
            j += 2;
        }
    }
    let k = kept.len();
    let w = vectors.then(|| {
        Mat::from_fn(m, 2 * k, |i, c| {
            if c < k {
                u[(i, kept[c].1)]
            } else {
                kept[c - k].2.map_or(0.0, |(col, sign)| sign * u[(i, col)])
            }
        })
    });
    Ok(FirstOrder {
        vals: kept.iter().map(|x| x.0).collect(),
        rho,
        w,
    })
}

/// `A = [[0, σI], [−K̂/σ, −Ĉ]]`, `σ = sqrt(mean |K̂_ii|)` (see [`first_order_eigen`]).
pub(crate) fn first_order_matrix_of(khat: &Mat<f64>, chat: Option<&Mat<f64>>) -> Mat<f64> {
    let m = khat.nrows();
    let sigma = balance(khat);
    let mut a = Mat::<f64>::zeros(2 * m, 2 * m);
    for i in 0..m {
        a[(i, m + i)] = sigma;
    }
    for j in 0..m {
        for i in 0..m {
            a[(m + i, j)] = -khat[(i, j)] / sigma;
        }
    }
    if let Some(c) = chat {
        for j in 0..m {
            for i in 0..m {
                a[(m + i, m + j)] = -c[(i, j)];
            }
        }
    }
    a
}

/// The balancing scale `σ = sqrt(mean |K̂_ii|)` of [`first_order_matrix_of`] (1 when that is
/// 0 or not finite).
pub(crate) fn balance(khat: &Mat<f64>) -> f64 {
    let m = khat.nrows();
    let mean_k = (0..m).map(|i| khat[(i, i)].abs()).sum::<f64>() / m.max(1) as f64;
    if mean_k > 0.0 && mean_k.is_finite() {
        mean_k.sqrt()
    } else {
        1.0
    }
}

/// (Re λ, Im λ, packed right eigenvectors, max |λ|) of [`real_evd`].
pub(crate) type RealEvd = (Vec<f64>, Vec<f64>, Mat<f64>, f64);

/// Every eigenvalue (real and imaginary parts) of a real square matrix, its right eigenvectors
/// when `vectors` (faer's packed real form: a complex pair at columns j, j+1 holds Re and Im of
/// the vector of `s_re[j] + i s_im[j]`; an empty matrix otherwise) and the largest |eigenvalue|,
/// by faer's dense `evd_real` (Hessenberg + real Schur; sequential below 512).
///
/// # Errors
/// Non-convergence and non-finite eigenvalues.
pub(crate) fn real_evd(a: &Mat<f64>, vectors: bool) -> Result<RealEvd, CeaError> {
    let n2 = a.nrows();
    // Small problems run sequentially: on the shared 2-core machine the projected sweep's
    // 200×200 solves took ~25 ms/step sequential vs ~30 ms with rayon (noisy, load ~4).
    let par = if n2 < SEQ_BELOW {
        faer::Par::Seq
    } else {
        faer::get_global_parallelism()
    };
    let want = if vectors {
        ComputeEigenvectors::Yes
    } else {
        ComputeEigenvectors::No
    };
    let mut s_re = Diag::<f64>::zeros(n2);
    let mut s_im = Diag::<f64>::zeros(n2);
    let mut u = Mat::<f64>::zeros(if vectors { n2 } else { 0 }, if vectors { n2 } else { 0 });
    let mut mem = MemBuffer::new(evd_scratch::<f64>(
        n2,
        ComputeEigenvectors::No,
        want,
        par,
        Default::default(),
    ));
    evd_real(
        a.as_ref(),
        s_re.as_mut(),
        s_im.as_mut(),
        None,
        if vectors { Some(u.as_mut()) } else { None },
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| CeaError::NoConvergence {
        what: if vectors {
            "eigendecomposition"
        } else {
            "eigenvalues"
        },
        n: n2,
    })?;
    let (s_re, s_im) = (s_re.column_vector(), s_im.column_vector());
    let mut rho = 0.0f64;
    for j in 0..n2 {
        let (re, im) = (s_re[j], s_im[j]);
        if !(re.is_finite() && im.is_finite()) {
            return Err(CeaError::NonFinite {
                what: "eigenvalue",
                row: j,
                col: 0,
                value: if re.is_finite() { im } else { re },
            });
        }
        rho = rho.max(re.hypot(im));
    }
    let re: Vec<f64> = (0..n2).map(|j| s_re[j]).collect();
    let im: Vec<f64> = (0..n2).map(|j| s_im[j]).collect();
    Ok((re, im, u, rho))
}
