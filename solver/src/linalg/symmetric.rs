//! Products with symmetric constant matrices stored by their upper triangle (the residual's
//! M v' + B v + K u, the energy forms vᵀMv, vᵀBv, uᵀKu, the Newton solve's K r_u).
//!
//! # Reference
//! For symmetric A with diagonal d and strictly upper part U (A = diag(d) + U + Uᵀ):
//! $$ (A x)_i = d_i x_i + \sum_{j>i} U_{ij} x_j + \sum_{j<i} U_{ji} x_j,\qquad
//! x^T A x = \sum_i d_i x_i^2 + 2 \sum_i x_i \sum_{j>i} U_{ij} x_j .$$
//! Row i of U serves both sums of the product: a dot product with x (row i) and an update
//! y_j += U_ij x_i of the later rows (column i of Uᵀ). Half the entries are stored and read;
//! the quadratic form does half the multiply–adds.
//!
//! # Storage
//! The strictly upper triangle of the union pattern of the matrices is stored by rows as runs
//! of consecutive columns, as [`super::sparse`] stores whole matrices, with two changes for the
//! short runs of reduced models (about 20 columns): runs closer than four columns are merged,
//! and each run is padded with zeros to a multiple of four columns (within the matrix), so
//! that the inner loops are whole four-lane chunks; the partial sums of a row stay in vector
//! accumulators across its runs and are reduced once per row. The padding and the order of
//! the additions change the results by round-off only.
//!
//! # When it applies
//! [`Products::new`] checks every pair: the upper triangle stands for the matrix when
//! |a_ij − a_ji| ≤ 8 ε · max(|a_ij|, |a_ji|, √|a_ii a_jj|) (exactly symmetric matrices, as
//! squeal's reductions give, and matrices symmetric to the round-off of their assembly, as a
//! stored model may be); otherwise the whole matrices are kept ([`RunRows`]).

use faer::Mat;

use super::sparse::{dispatch, RunRows};
use crate::{Real, SolverError};

/// Index type of the patterns.
type Ix = u32;

/// Runs are padded to multiples of this many columns (the lanes of AVX2's f64 vectors).
const W: usize = 4;

/// Symmetric matrices of one size: their diagonals and the strictly upper triangle of their
/// union pattern in padded runs.
#[derive(Debug, Clone)]
pub(crate) struct SymRuns {
    n: usize,
    /// Diagonal of matrix m: `diag[m]`.
    diag: Vec<Vec<Real>>,
    /// Runs of row i: `row_ptr[i]..row_ptr[i + 1]`.
    row_ptr: Vec<Ix>,
    /// First column of each run.
    col: Vec<Ix>,
    /// Offset of each run's values (length runs + 1).
    off: Vec<Ix>,
    /// Values of matrix m over the runs (padding zeros included).
    val: Vec<Vec<Real>>,
    /// Non-zero entries of the whole union pattern (both triangles and the diagonal).
    nnz: usize,
}

/// True when `a` is symmetric to round-off (module documentation).
fn symmetric(a: &Mat<Real>) -> bool {
    let n = a.nrows();
    if a.ncols() != n {
        return false;
    }
    let tol = 8.0 * Real::EPSILON;
    for j in 0..n {
        for i in 0..j {
            let (x, y) = (a[(i, j)], a[(j, i)]);
            if x == y {
                continue;
            }
            let scale = x
                .abs()
                .max(y.abs())
                .max((a[(i, i)] * a[(j, j)]).abs().sqrt());
            // False for NaN (an entry or the scale): not symmetric.
            let close = (x - y).abs() <= tol * scale;
            if !close {
                return false;
            }
        }
    }
    true
}

impl SymRuns {
    /// The upper triangles of `mats` (square, one size, symmetric: the caller checks).
    fn from_dense(mats: &[&Mat<Real>], what: &'static str) -> Result<Self, SolverError> {
        let n = mats.first().map_or(0, |a| a.nrows());
        let nz = |i: usize, j: usize| mats.iter().any(|a| a[(i, j)] != 0.0);
        let mut row_ptr = vec![0 as Ix];
        let (mut col, mut off) = (Vec::new(), vec![0 as Ix]);
        let mut val = vec![Vec::new(); mats.len()];
        let mut nnz = 0;
        let mut runs: Vec<(usize, usize)> = Vec::new();
        for i in 0..n {
            nnz += (0..n).filter(|&j| nz(i, j)).count();
            // Runs of the strictly upper part, merged across gaps of fewer than W columns.
            runs.clear();
            for j in i + 1..n {
                if !nz(i, j) {
                    continue;
                }
                match runs.last_mut() {
                    Some((_, e)) if j < *e + W => *e = j + 1,
                    _ => runs.push((j, j + 1)),
                }
            }
            for &(c, e) in &runs {
                // Padded to a multiple of W inside [0, n): to the right, else to the left.
                let len = (e - c).div_ceil(W) * W;
                let (c0, e0) = if c + len <= n {
                    (c, c + len)
                } else if len <= n {
                    (n - len, n)
                } else {
                    (c, e)
                };
                col.push(c0 as Ix);
                for (v, a) in val.iter_mut().zip(mats) {
                    v.extend((c0..e0).map(|j| if j >= c && j < e { a[(i, j)] } else { 0.0 }));
                }
                if val[0].len() >= Ix::MAX as usize {
                    return Err(SolverError::DimensionMismatch {
                        what,
                        expected: Ix::MAX as usize,
                        got: val[0].len(),
                    });
                }
                off.push(val[0].len() as Ix);
            }
            row_ptr.push(col.len() as Ix);
        }
        let diag = mats
            .iter()
            .map(|a| (0..n).map(|i| a[(i, i)]).collect())
            .collect();
        Ok(Self {
            n,
            diag,
            row_ptr,
            col,
            off,
            val,
            nnz,
        })
    }
}

/// The kernels of [`SymRuns`] with `NM` matrices, SIMD-dispatched.
enum Kernel<'a, const NM: usize> {
    /// y ← (y if `add`, else 0) + α Σ_m A_m x_m.
    Apply {
        x: [&'a [Real]; NM],
        y: &'a mut [Real],
        add: bool,
        alpha: Real,
    },
    /// x_mᵀ A_m x_m.
    Forms { x: [&'a [Real]; NM] },
}

struct Run<'a, const NM: usize>(&'a SymRuns, Kernel<'a, NM>);

impl<const NM: usize> pulp::WithSimd for Run<'_, NM> {
    type Output = [Real; NM];
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> [Real; NM] {
        let s = self.0;
        let mut out = [0.0; NM];
        let zero = simd.splat_f64s(0.0);
        match self.1 {
            Kernel::Apply { x, y, add, alpha } => {
                for (i, yi) in y.iter_mut().enumerate() {
                    let mut d = 0.0;
                    for m in 0..NM {
                        d += s.diag[m][i] * x[m][i];
                    }
                    *yi = if add { *yi + alpha * d } else { alpha * d };
                }
                for i in 0..s.n {
                    // Row i's dot products in vector accumulators (reduced once per row).
                    let mut acc = [zero; NM];
                    let mut tail = 0.0;
                    let xi: [Real; NM] = std::array::from_fn(|m| alpha * x[m][i]);
                    let xs: [S::f64s; NM] = std::array::from_fn(|m| simd.splat_f64s(xi[m]));
                    for r in s.row_ptr[i] as usize..s.row_ptr[i + 1] as usize {
                        let (c, a, b) =
                            (s.col[r] as usize, s.off[r] as usize, s.off[r + 1] as usize);
                        let e = c + b - a;
                        let (yh, yt) = S::as_mut_simd_f64s(&mut y[c..e]);
                        let q = yh.len();
                        let vh: [&[S::f64s]; NM] =
                            std::array::from_fn(|m| &S::as_simd_f64s(&s.val[m][a..b]).0[..q]);
                        let xh: [&[S::f64s]; NM] =
                            std::array::from_fn(|m| &S::as_simd_f64s(&x[m][c..e]).0[..q]);
                        // ... and the later rows': y_j += Σ_m α U_m,ij x_m,i.
                        for (k, yk) in yh.iter_mut().enumerate() {
                            let mut t = zero;
                            for m in 0..NM {
                                acc[m] = simd.mul_add_e_f64s(vh[m][k], xh[m][k], acc[m]);
                                t = simd.mul_add_e_f64s(vh[m][k], xs[m], t);
                            }
                            *yk = simd.add_f64s(*yk, t);
                        }
                        let l = e - c - yt.len();
                        for (p, yj) in yt.iter_mut().enumerate() {
                            for m in 0..NM {
                                let v = s.val[m][a + l + p];
                                tail += v * x[m][c + l + p];
                                *yj += v * xi[m];
                            }
                        }
                    }
                    let mut d = tail;
                    for a in acc {
                        d += simd.reduce_sum_f64s(a);
                    }
                    y[i] += alpha * d;
                }
            }
            Kernel::Forms { x } => {
                for i in 0..s.n {
                    // Two accumulators per matrix (even and odd chunks) halve the chain of
                    // dependent additions.
                    let mut acc = [[zero; 2]; NM];
                    let mut tail = [0.0; NM];
                    for r in s.row_ptr[i] as usize..s.row_ptr[i + 1] as usize {
                        let (c, a, b) =
                            (s.col[r] as usize, s.off[r] as usize, s.off[r + 1] as usize);
                        let e = c + b - a;
                        let q = S::as_simd_f64s(&s.val[0][a..b]).0.len();
                        let vh: [&[S::f64s]; NM] =
                            std::array::from_fn(|m| &S::as_simd_f64s(&s.val[m][a..b]).0[..q]);
                        let xh: [&[S::f64s]; NM] =
                            std::array::from_fn(|m| &S::as_simd_f64s(&x[m][c..e]).0[..q]);
                        for k in 0..q / 2 {
                            for m in 0..NM {
                                let [a0, a1] = &mut acc[m];
                                let (k0, k1) = (2 * k, 2 * k + 1);
                                *a0 = simd.mul_add_e_f64s(vh[m][k0], xh[m][k0], *a0);
                                *a1 = simd.mul_add_e_f64s(vh[m][k1], xh[m][k1], *a1);
                            }
                        }
                        if q % 2 == 1 {
                            for m in 0..NM {
                                let k = q - 1;
                                acc[m][0] = simd.mul_add_e_f64s(vh[m][k], xh[m][k], acc[m][0]);
                            }
                        }
                        for j in q * S::F64_LANES..b - a {
                            for m in 0..NM {
                                tail[m] += s.val[m][a + j] * x[m][c + j];
                            }
                        }
                    }
                    for m in 0..NM {
                        let xi = x[m][i];
                        let d = simd.reduce_sum_f64s(simd.add_f64s(acc[m][0], acc[m][1])) + tail[m];
                        out[m] += xi * (s.diag[m][i] * xi + 2.0 * d);
                    }
                }
            }
        }
        out
    }
}

/// Products with constant square matrices of one size: by their upper triangles when all are
/// symmetric to round-off, else by the whole matrices.
#[derive(Debug, Clone)]
pub(crate) enum Products {
    Symmetric(SymRuns),
    General(RunRows),
}

impl Products {
    /// The products of `mats` (square, one size; `what` names them in errors).
    pub fn new(mats: &[&Mat<Real>], what: &'static str) -> Result<Self, SolverError> {
        let n = mats.first().map_or(0, |a| a.nrows());
        if let Some(a) = mats.iter().find(|a| a.nrows() != n || a.ncols() != n) {
            return Err(SolverError::DimensionMismatch {
                what,
                expected: n,
                got: if a.nrows() != n { a.nrows() } else { a.ncols() },
            });
        }
        if mats.iter().all(|a| symmetric(a)) {
            Ok(Self::Symmetric(SymRuns::from_dense(mats, what)?))
        } else {
            Ok(Self::General(RunRows::from_dense(mats, what)?))
        }
    }

    /// Whether the upper triangles are used.
    pub fn is_symmetric(&self) -> bool {
        matches!(self, Self::Symmetric(_))
    }

    /// Non-zero entries of the union pattern (whole matrices).
    pub fn nnz(&self) -> usize {
        match self {
            Self::Symmetric(s) => s.nnz,
            Self::General(g) => g.nnz(),
        }
    }

    /// y ← α A₀ x (+ y when `add`), with the first matrix.
    pub fn apply(&self, x: &[Real], y: &mut [Real], add: bool, alpha: Real) {
        match self {
            Self::Symmetric(s) => {
                debug_assert!(x.len() == s.n && y.len() == s.n);
                dispatch(Run::<1>(
                    s,
                    Kernel::Apply {
                        x: [x],
                        y,
                        add,
                        alpha,
                    },
                ));
            }
            Self::General(g) => g.apply(0, x, y, add, alpha),
        }
    }

    /// r ← A₀ x₀ + A₁ x₁ + A₂ x₂ (three matrices).
    pub fn apply3(&self, x0: &[Real], x1: &[Real], x2: &[Real], r: &mut [Real]) {
        match self {
            Self::Symmetric(s) => {
                debug_assert!(s.val.len() == 3 && r.len() == s.n);
                dispatch(Run::<3>(
                    s,
                    Kernel::Apply {
                        x: [x0, x1, x2],
                        y: r,
                        add: false,
                        alpha: 1.0,
                    },
                ));
            }
            Self::General(g) => g.apply3(x0, x1, x2, r),
        }
    }

    /// (vᵀ A₀ v, vᵀ A₁ v, uᵀ A₂ u) (three matrices).
    pub fn quadratic_forms3(&self, v: &[Real], u: &[Real]) -> [Real; 3] {
        match self {
            Self::Symmetric(s) => {
                debug_assert!(s.val.len() == 3 && v.len() == s.n && u.len() == s.n);
                dispatch(Run::<3>(s, Kernel::Forms { x: [v, v, u] }))
            }
            Self::General(g) => g.quadratic_forms3(v, u),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense_mv(a: &Mat<Real>, x: &[Real]) -> Vec<Real> {
        (0..a.nrows())
            .map(|i| (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum())
            .collect()
    }

    /// A pseudo-random symmetric matrix, about 40 % of its entries zero (runs of all
    /// lengths and gaps, some rows empty off the diagonal).
    fn sym_sample(n: usize, seed: u64) -> Mat<Real> {
        let mut s = seed;
        let mut a = Mat::zeros(n, n);
        for j in 0..n {
            for i in 0..=j {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let r = (s >> 11) as Real / (1u64 << 53) as Real;
                let x = if r < 0.4 || (i != j && j % 7 == 3) {
                    0.0
                } else {
                    r - 0.7
                };
                a[(i, j)] = x;
                a[(j, i)] = x;
            }
        }
        a
    }

    fn dot(a: &[Real], b: &[Real]) -> Real {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// The products by upper triangles equal the dense ones, for sizes below, at and above
    /// the chunk width (runs that cannot be padded inside the matrix included).
    #[test]
    fn symmetric_products_match_dense() {
        for n in [1, 3, 4, 6, 23, 40] {
            let (m, b, k) = (sym_sample(n, 2), sym_sample(n, 3), sym_sample(n, 4));
            let p = Products::new(&[&m, &b, &k], "mbk").unwrap();
            assert!(p.is_symmetric());
            let x0: Vec<Real> = (0..n).map(|i| (i as Real).sin()).collect();
            let x1: Vec<Real> = (0..n).map(|i| (i as Real).cos()).collect();
            let x2: Vec<Real> = (0..n).map(|i| 0.1 * i as Real - 0.3).collect();
            let mut r = vec![Real::NAN; n];
            p.apply3(&x0, &x1, &x2, &mut r);
            let (a0, a1, a2) = (dense_mv(&m, &x0), dense_mv(&b, &x1), dense_mv(&k, &x2));
            for i in 0..n {
                assert!(
                    (r[i] - (a0[i] + a1[i] + a2[i])).abs() < 1e-12,
                    "n = {n}, row {i}"
                );
            }
            let q = p.quadratic_forms3(&x0, &x2);
            assert!((q[0] - dot(&x0, &a0)).abs() < 1e-12);
            assert!((q[1] - dot(&x0, &dense_mv(&b, &x0))).abs() < 1e-12);
            assert!((q[2] - dot(&x2, &a2)).abs() < 1e-12);
            let pk = Products::new(&[&k], "k").unwrap();
            let mut y = vec![1.0; n];
            pk.apply(&x2, &mut y, true, -2.0);
            for i in 0..n {
                assert!((y[i] - (1.0 - 2.0 * a2[i])).abs() < 1e-12);
            }
            pk.apply(&x2, &mut y, false, 0.5);
            for i in 0..n {
                assert!((y[i] - 0.5 * a2[i]).abs() < 1e-12);
            }
            let nnz = (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .filter(|&(i, j)| m[(i, j)] != 0.0 || b[(i, j)] != 0.0 || k[(i, j)] != 0.0)
                .count();
            assert_eq!(p.nnz(), nnz);
        }
    }

    /// A matrix symmetric to round-off uses the upper triangle; one that is not (or has a
    /// NaN) keeps the whole matrix, with the same products.
    #[test]
    fn asymmetry_beyond_round_off_keeps_the_whole_matrix() {
        let n = 9;
        let x: Vec<Real> = (0..n).map(|i| 1.0 - 0.2 * i as Real).collect();
        let mut a = sym_sample(n, 5);
        a[(2, 0)] = 1.0;
        a[(0, 2)] = 1.0 + 2.0 * Real::EPSILON;
        assert!(Products::new(&[&a], "a").unwrap().is_symmetric());
        a[(0, 2)] = 1.0 + 1e-9;
        let p = Products::new(&[&a], "a").unwrap();
        assert!(!p.is_symmetric());
        let mut y = vec![0.0; n];
        p.apply(&x, &mut y, false, 1.0);
        let want = dense_mv(&a, &x);
        for i in 0..n {
            assert!((y[i] - want[i]).abs() < 1e-13);
        }
        a[(0, 2)] = Real::NAN;
        a[(2, 0)] = Real::NAN;
        assert!(!Products::new(&[&a], "a").unwrap().is_symmetric());
        let c = Mat::<Real>::zeros(n, n + 1);
        assert!(Products::new(&[&a, &c], "a, c").is_err());
    }
}
