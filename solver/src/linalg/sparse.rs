//! Sparse products with the constant matrices of a time step (compressed rows of contiguous
//! runs, built once).
//!
//! Reduced Craig–Bampton matrices are block-sparse: a component's modal coordinates couple only
//! with its own boundary DOFs and the modal block is diagonal, so the study brake's M, B, K are
//! 12–30 % non-zero, in runs of about 20 consecutive columns per row, and G has a handful of
//! entries per row. [`RunRows`] stores one or more matrices on their union pattern as runs of
//! consecutive columns: the inner loop of a product is then a dense dot product over a run
//! (four-lane partial sums, which the compiler vectorises), with no index per entry. The
//! residual needs M v' + B v + K u every Newton iteration and the energy bookkeeping the three
//! quadratic forms vᵀMv, vᵀBv, uᵀKu every step: one pass over the pattern serves all three.
//!
//! Indices are `u32`; the constructors refuse patterns beyond `u32::MAX` entries. Nothing
//! allocates after construction.

use faer::Mat;

use crate::{Real, SolverError};

/// Index type of the patterns.
type Ix = u32;

/// Runs `op` with the best SIMD instruction set of the CPU (AVX2/FMA where present, chosen
/// at run time by pulp, as faer's kernels are): `op.with_simd` and what it calls with
/// `#[inline(always)]` are compiled for it.
#[inline(always)]
pub(crate) fn dispatch<Op: pulp::WithSimd>(op: Op) -> Op::Output {
    pulp::Arch::new().dispatch(op)
}

/// The products below as SIMD-dispatched operations.
enum Kernel<'a> {
    Apply {
        m: usize,
        x: &'a [Real],
        y: &'a mut [Real],
        add: bool,
        alpha: Real,
    },
    Apply3 {
        x: [&'a [Real]; 3],
        r: &'a mut [Real],
    },
    Forms3 {
        v: &'a [Real],
        u: &'a [Real],
    },
}

struct Run<'a>(&'a RunRows, Kernel<'a>);

impl pulp::WithSimd for Run<'_> {
    type Output = [Real; 3];
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> [Real; 3] {
        let rows = self.0;
        match self.1 {
            Kernel::Apply {
                m,
                x,
                y,
                add,
                alpha,
            } => {
                for (i, yi) in y.iter_mut().enumerate() {
                    let s = rows.row_dot(m, i, x);
                    *yi = if add { *yi + alpha * s } else { alpha * s };
                }
                [0.0; 3]
            }
            Kernel::Apply3 { x, r } => {
                for (i, ri) in r.iter_mut().enumerate() {
                    let s = rows.row_dot3(i, x[0], x[1], x[2]);
                    *ri = s[0] + s[1] + s[2];
                }
                [0.0; 3]
            }
            Kernel::Forms3 { v, u } => {
                let mut q = [0.0; 3];
                for i in 0..rows.nrows {
                    let s = rows.row_dot3(i, v, v, u);
                    q[0] += v[i] * s[0];
                    q[1] += v[i] * s[1];
                    q[2] += u[i] * s[2];
                }
                q
            }
        }
    }
}

/// Σ a_k x_k with four partial sums (vectorised; the order of the additions differs from a
/// sequential sum only by rounding).
#[inline(always)]
fn dot(a: &[Real], x: &[Real]) -> Real {
    let n = a.len().min(x.len());
    let (a, x) = (&a[..n], &x[..n]);
    let mut s = [0.0; 4];
    let (ac, ar) = a.split_at(n - n % 4);
    let (xc, xr) = x.split_at(n - n % 4);
    for (ca, cx) in ac.chunks_exact(4).zip(xc.chunks_exact(4)) {
        for l in 0..4 {
            s[l] += ca[l] * cx[l];
        }
    }
    let mut t = (s[0] + s[1]) + (s[2] + s[3]);
    for (p, q) in ar.iter().zip(xr) {
        t += p * q;
    }
    t
}

/// `nm` matrices of equal shape on their union pattern, stored by rows as runs of consecutive
/// columns; matrix `m`'s values of run r are `val[m][off[r]..off[r + 1]]`.
#[derive(Debug, Clone)]
pub(crate) struct RunRows {
    nrows: usize,
    ncols: usize,
    /// Runs of row i: `row_ptr[i]..row_ptr[i + 1]`.
    row_ptr: Vec<Ix>,
    /// First column of each run.
    col: Vec<Ix>,
    /// Offset of each run's values (length runs + 1).
    off: Vec<Ix>,
    val: Vec<Vec<Real>>,
}

impl RunRows {
    /// The union pattern of `mats` (all of one shape): an entry is kept where any is non-zero.
    pub fn from_dense(mats: &[&Mat<Real>], what: &'static str) -> Result<Self, SolverError> {
        let (nrows, ncols) = mats.first().map_or((0, 0), |a| (a.nrows(), a.ncols()));
        for a in mats {
            if a.nrows() != nrows || a.ncols() != ncols {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: nrows,
                    got: a.nrows(),
                });
            }
        }
        let mut row_ptr = Vec::with_capacity(nrows + 1);
        let mut col = Vec::new();
        let mut off = vec![0];
        let mut val = vec![Vec::new(); mats.len()];
        row_ptr.push(0);
        for i in 0..nrows {
            let mut open = false;
            for j in 0..ncols {
                let nz = mats.iter().any(|a| a[(i, j)] != 0.0);
                if nz {
                    if !open {
                        col.push(j as Ix);
                        off.push(*off.last().expect("starts with 0"));
                    }
                    for (v, a) in val.iter_mut().zip(mats) {
                        v.push(a[(i, j)]);
                    }
                    *off.last_mut().expect("a run is open") += 1;
                }
                open = nz;
            }
            if val[0].len() >= Ix::MAX as usize || col.len() >= Ix::MAX as usize {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: Ix::MAX as usize,
                    got: val[0].len(),
                });
            }
            row_ptr.push(col.len() as Ix);
        }
        Ok(Self {
            nrows,
            ncols,
            row_ptr,
            col,
            off,
            val,
        })
    }

    /// Aᵀ of a dense A (one matrix).
    pub fn transpose_of_dense(a: &Mat<Real>, what: &'static str) -> Result<Self, SolverError> {
        Self::from_dense(&[&a.transpose().to_owned()], what)
    }

    /// Stored entries (of the union pattern).
    pub fn nnz(&self) -> usize {
        self.val.first().map_or(0, Vec::len)
    }

    /// (A_m x)_i.
    #[inline(always)]
    pub fn row_dot(&self, m: usize, i: usize, x: &[Real]) -> Real {
        let val = &self.val[m];
        let mut s = 0.0;
        for r in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            let (c, a, b) = (
                self.col[r] as usize,
                self.off[r] as usize,
                self.off[r + 1] as usize,
            );
            s += dot(&val[a..b], &x[c..c + b - a]);
        }
        s
    }

    /// y ← α A_m x (+ y when `add`).
    pub fn apply(&self, m: usize, x: &[Real], y: &mut [Real], add: bool, alpha: Real) {
        debug_assert!(x.len() == self.ncols && y.len() == self.nrows);
        dispatch(Run(
            self,
            Kernel::Apply {
                m,
                x,
                y,
                add,
                alpha,
            },
        ));
    }

    /// Per row i: ((A₀ x₀)_i, (A₁ x₁)_i, (A₂ x₂)_i) in one pass over the row's runs.
    #[inline(always)]
    fn row_dot3(&self, i: usize, x0: &[Real], x1: &[Real], x2: &[Real]) -> [Real; 3] {
        let (v0, v1, v2) = (&self.val[0], &self.val[1], &self.val[2]);
        let mut s = [0.0; 3];
        for r in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            let (c, a, b) = (
                self.col[r] as usize,
                self.off[r] as usize,
                self.off[r + 1] as usize,
            );
            let e = c + b - a;
            s[0] += dot(&v0[a..b], &x0[c..e]);
            s[1] += dot(&v1[a..b], &x1[c..e]);
            s[2] += dot(&v2[a..b], &x2[c..e]);
        }
        s
    }

    /// r ← A₀ x₀ + A₁ x₁ + A₂ x₂ (three matrices stored together).
    pub fn apply3(&self, x0: &[Real], x1: &[Real], x2: &[Real], r: &mut [Real]) {
        debug_assert!(self.val.len() == 3 && r.len() == self.nrows);
        dispatch(Run(self, Kernel::Apply3 { x: [x0, x1, x2], r }));
    }

    /// (vᵀ A₀ v, vᵀ A₁ v, uᵀ A₂ u) in one pass (three square matrices stored together).
    pub fn quadratic_forms3(&self, v: &[Real], u: &[Real]) -> [Real; 3] {
        debug_assert!(self.val.len() == 3 && v.len() == self.nrows && u.len() == self.nrows);
        dispatch(Run(self, Kernel::Forms3 { v, u }))
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

    /// A pseudo-random matrix with about a third of its entries zero (runs of all lengths).
    fn sample(n: usize, m: usize, seed: u64) -> Mat<Real> {
        let mut s = seed;
        Mat::from_fn(n, m, |_, _| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = (s >> 11) as Real / (1u64 << 53) as Real;
            if r < 0.35 {
                0.0
            } else {
                r - 0.6
            }
        })
    }

    #[test]
    fn single_matrix_products_match_dense() {
        let a = sample(7, 13, 1);
        let x: Vec<Real> = (0..13).map(|i| 0.3 * i as Real - 1.0).collect();
        let rows = RunRows::from_dense(&[&a], "a").unwrap();
        assert!(rows.nnz() < 7 * 13 && rows.col.len() > 7);
        let mut y = vec![1.0; 7];
        rows.apply(0, &x, &mut y, true, -2.0);
        let want = dense_mv(&a, &x);
        for i in 0..7 {
            assert!((y[i] - (1.0 - 2.0 * want[i])).abs() < 1e-13);
            assert!((rows.row_dot(0, i, &x) - want[i]).abs() < 1e-13);
        }
        let at = RunRows::transpose_of_dense(&a, "a").unwrap();
        let z: Vec<Real> = (0..7).map(|i| i as Real - 2.5).collect();
        let mut w = vec![0.0; 13];
        at.apply(0, &z, &mut w, false, 1.0);
        let want = dense_mv(&a.transpose().to_owned(), &z);
        for j in 0..13 {
            assert!((w[j] - want[j]).abs() < 1e-13);
        }
    }

    #[test]
    fn three_matrix_products_and_forms_match_dense() {
        let n = 23;
        let (m, b, k) = (sample(n, n, 2), sample(n, n, 3), sample(n, n, 4));
        let f = RunRows::from_dense(&[&m, &b, &k], "mbk").unwrap();
        let x0: Vec<Real> = (0..n).map(|i| (i as Real).sin()).collect();
        let x1: Vec<Real> = (0..n).map(|i| (i as Real).cos()).collect();
        let x2: Vec<Real> = (0..n).map(|i| 0.1 * i as Real).collect();
        let mut r = vec![Real::NAN; n];
        f.apply3(&x0, &x1, &x2, &mut r);
        let (a0, a1, a2) = (dense_mv(&m, &x0), dense_mv(&b, &x1), dense_mv(&k, &x2));
        for i in 0..n {
            assert!((r[i] - (a0[i] + a1[i] + a2[i])).abs() < 1e-12);
        }
        let dot = |a: &[Real], b: &[Real]| a.iter().zip(b).map(|(x, y)| x * y).sum::<Real>();
        let q = f.quadratic_forms3(&x0, &x2);
        assert!((q[0] - dot(&x0, &a0)).abs() < 1e-12);
        assert!((q[1] - dot(&x0, &dense_mv(&b, &x0))).abs() < 1e-12);
        assert!((q[2] - dot(&x2, &a2)).abs() < 1e-12);
    }

    #[test]
    fn mismatched_shapes_are_an_error() {
        let (a, b) = (sample(3, 3, 5), sample(4, 3, 6));
        assert!(RunRows::from_dense(&[&a, &b], "a, b").is_err());
    }
}
