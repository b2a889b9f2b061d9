//! Splitting a sparse matrix into interior/boundary blocks, and small sparse helpers.

use crate::error::ReductionError;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::Mat;
use squeal_meshes::Real;

/// Sparse matrix type of the inputs (full symmetric storage).
pub type Sparse = SparseColMat<usize, Real>;

/// Where each free DOF goes: boundary position or interior position.
#[derive(Debug, Clone)]
pub(crate) struct Partition {
    /// For each free DOF: `Ok(j)` = boundary position j, `Err(j)` = interior position j.
    pub slot: Vec<Result<usize, usize>>,
    /// Interior DOFs in increasing order.
    pub interior: Vec<usize>,
    pub n_boundary: usize,
}

impl Partition {
    /// Validates `boundary` (in range, no repeats) and builds the partition of `n` DOFs.
    pub fn new(n: usize, boundary: &[usize]) -> Result<Self, ReductionError> {
        let mut slot: Vec<Option<Result<usize, usize>>> = vec![None; n];
        for (pos, &b) in boundary.iter().enumerate() {
            if b >= n {
                return Err(ReductionError::BadBoundary { index: b, position: pos, reason: "out of range", n });
            }
            if slot[b].is_some() {
                return Err(ReductionError::BadBoundary { index: b, position: pos, reason: "repeated", n });
            }
            slot[b] = Some(Ok(pos));
        }
        let mut interior = Vec::with_capacity(n - boundary.len());
        let slot = slot
            .into_iter()
            .enumerate()
            .map(|(i, s)| {
                s.unwrap_or_else(|| {
                    interior.push(i);
                    Err(interior.len() - 1)
                })
            })
            .collect();
        Ok(Self { slot, interior, n_boundary: boundary.len() })
    }
}

/// Blocks of one matrix: `ii` sparse (n_i × n_i), `ib` sparse (n_i × n_b), `bb` dense.
pub(crate) struct Blocks {
    pub ii: Sparse,
    pub ib: Sparse,
    pub bb: Mat<Real>,
}

/// Checks that `a` is `n × n` with finite entries.
pub(crate) fn check_square(a: &Sparse, n: usize, what: &str) -> Result<(), ReductionError> {
    if a.nrows() != n || a.ncols() != n {
        return Err(ReductionError::ShapeMismatch {
            what: what.to_string(),
            rows: a.nrows(),
            cols: a.ncols(),
            expected_rows: n,
            expected_cols: n,
        });
    }
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            if !v[p].is_finite() {
                return Err(ReductionError::NonFinite { what: what.to_string(), row: ri[p], col: j, value: v[p] });
            }
        }
    }
    Ok(())
}

/// Builds a CSC matrix from per-column (row, value) lists; sorts each column.
fn from_columns(nrows: usize, cols: Vec<Vec<(usize, Real)>>) -> Sparse {
    let ncols = cols.len();
    let mut col_ptr = Vec::with_capacity(ncols + 1);
    let nnz: usize = cols.iter().map(Vec::len).sum();
    let mut row_idx = Vec::with_capacity(nnz);
    let mut val = Vec::with_capacity(nnz);
    col_ptr.push(0);
    for mut c in cols {
        if !c.windows(2).all(|w| w[0].0 < w[1].0) {
            c.sort_by_key(|e| e.0);
            c.dedup_by(|a, b| {
                if a.0 == b.0 {
                    b.1 += a.1;
                    true
                } else {
                    false
                }
            });
        }
        for (r, x) in c {
            row_idx.push(r);
            val.push(x);
        }
        col_ptr.push(row_idx.len());
    }
    SparseColMat::new(SymbolicSparseColMat::new_checked(nrows, ncols, col_ptr, None, row_idx), val)
}

/// Splits `a` (full storage) into K_ii, K_ib and dense K_bb.
pub(crate) fn split(a: &Sparse, part: &Partition) -> Blocks {
    let ni = part.interior.len();
    let nb = part.n_boundary;
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    let mut ii: Vec<Vec<(usize, Real)>> = vec![Vec::new(); ni];
    let mut ib: Vec<Vec<(usize, Real)>> = vec![Vec::new(); nb];
    let mut bb = Mat::<Real>::zeros(nb, nb);
    for j in 0..a.ncols() {
        let range = cp[j]..cp[j + 1];
        match part.slot[j] {
            Err(cj) => {
                let col = &mut ii[cj];
                col.reserve(range.len());
                for p in range {
                    if let Err(r) = part.slot[ri[p]] {
                        col.push((r, v[p]));
                    }
                }
            }
            Ok(cj) => {
                for p in range {
                    match part.slot[ri[p]] {
                        Err(r) => ib[cj].push((r, v[p])),
                        Ok(r) => bb[(r, cj)] += v[p],
                    }
                }
            }
        }
    }
    Blocks { ii: from_columns(ni, ii), ib: from_columns(ni, ib), bb }
}

/// `a + alpha b` for two sparse matrices of the same shape (pattern union).
pub(crate) fn add_scaled(a: &Sparse, b: &Sparse, alpha: Real) -> Sparse {
    let n = a.ncols();
    let mut cols: Vec<Vec<(usize, Real)>> = Vec::with_capacity(n);
    for j in 0..n {
        let mut c = Vec::new();
        for (m, s) in [(a, 1.0), (b, alpha)] {
            let cp = m.symbolic().col_ptr();
            let ri = m.symbolic().row_idx();
            let v = m.val();
            for p in cp[j]..cp[j + 1] {
                c.push((ri[p], s * v[p]));
            }
        }
        c.sort_by_key(|e| e.0);
        cols.push(c);
    }
    from_columns(a.nrows(), cols)
}

/// Dense copy of a sparse matrix.
pub(crate) fn to_dense(a: &Sparse) -> Mat<Real> {
    let mut d = Mat::<Real>::zeros(a.nrows(), a.ncols());
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    for j in 0..a.ncols() {
        for p in cp[j]..cp[j + 1] {
            d[(ri[p], j)] += v[p];
        }
    }
    d
}

/// `dst = a · x` (sparse times dense), in parallel over the columns of `x`.
pub(crate) fn spmm(a: &Sparse, x: faer::MatRef<'_, Real>) -> Mat<Real> {
    let mut dst = Mat::<Real>::zeros(a.nrows(), x.ncols());
    faer::sparse::linalg::matmul::sparse_dense_matmul(
        dst.as_mut(),
        faer::Accum::Replace,
        a.as_ref(),
        x,
        1.0,
        faer::get_global_parallelism(),
    );
    dst
}
