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
                return Err(ReductionError::BadBoundary {
                    index: b,
                    position: pos,
                    reason: "out of range",
                    n,
                });
            }
            if slot[b].is_some() {
                return Err(ReductionError::BadBoundary {
                    index: b,
                    position: pos,
                    reason: "repeated",
                    n,
                });
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
        Ok(Self {
            slot,
            interior,
            n_boundary: boundary.len(),
        })
    }
}

/// Blocks of one matrix: `ii` sparse (n_i × n_i), `ib` sparse (n_i × n_b), `bb` dense.
pub(crate) struct Blocks {
    pub ii: Sparse,
    pub ib: Sparse,
    pub bb: Mat<Real>,
}

/// Checks that `a` is `n × n`, finite and symmetric (to 1e-10 of its largest entry).
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
                return Err(ReductionError::NonFinite {
                    what: what.to_string(),
                    row: ri[p],
                    col: j,
                    value: v[p],
                });
            }
        }
    }
    let tol = 1e-10 * v.iter().fold(0.0, |m: Real, x| m.max(x.abs()));
    // Entry (row, col); faer keeps row indices sorted within a column (binary search), with a
    // linear scan for matrices built unsorted.
    let sorted: Vec<bool> = (0..n)
        .map(|j| ri[cp[j]..cp[j + 1]].windows(2).all(|w| w[0] < w[1]))
        .collect();
    let entry = |col: usize, row: usize| -> Real {
        let rows = &ri[cp[col]..cp[col + 1]];
        if sorted[col] {
            rows.binary_search(&row).map_or(0.0, |k| v[cp[col] + k])
        } else {
            (cp[col]..cp[col + 1])
                .filter(|&p| ri[p] == row)
                .map(|p| v[p])
                .sum()
        }
    };
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i > j {
                let (a_ij, a_ji) = (entry(j, i), entry(i, j));
                if (a_ij - a_ji).abs() > tol {
                    return Err(ReductionError::NotSymmetric {
                        what: what.to_string(),
                        row: i,
                        col: j,
                        value: a_ij,
                        transposed: a_ji,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Builds a CSC matrix from per-column (row, value) lists; sorts each column.
pub(crate) fn from_columns(nrows: usize, cols: Vec<Vec<(usize, Real)>>) -> Sparse {
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
    SparseColMat::new(
        SymbolicSparseColMat::new_checked(nrows, ncols, col_ptr, None, row_idx),
        val,
    )
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
    Blocks {
        ii: from_columns(ni, ii),
        ib: from_columns(ni, ib),
        bb,
    }
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

/// `a · x` for a SYMMETRIC sparse `a` (full storage) and dense `x`.
///
/// Row i of the result is Σ_j a_ji x_j (column i of `a` read as row i): a gather over x's rows,
/// stored row-major so the inner loop runs over x's columns contiguously, in parallel over rows.
/// One pass over `a` for all columns of `x` (a column-by-column product would re-read `a` once
/// per column: 16 × 170 MB per Lanczos block on a 100k-DOF hex20 model).
pub(crate) fn sym_spmm(a: &Sparse, x: faer::MatRef<'_, Real>) -> Mat<Real> {
    let (n, p) = (a.ncols(), x.ncols());
    let mut out = Mat::<Real>::zeros(n, p);
    // Panels of 16 columns keep the gathered rows (128 bytes) and the panel (16 n values)
    // cache-friendly; `a` is read once per panel.
    const PANEL: usize = 16;
    for c0 in (0..p).step_by(PANEL) {
        let w = PANEL.min(p - c0);
        let panel = sym_spmm_panel(a, x.subcols(c0, w));
        out.subcols_mut(c0, w).copy_from(&panel);
    }
    out
}

fn sym_spmm_panel(a: &Sparse, x: faer::MatRef<'_, Real>) -> Mat<Real> {
    use rayon::prelude::*;
    let (n, p) = (a.ncols(), x.ncols());
    let mut xt = vec![0.0; n * p];
    for c in 0..p {
        for (i, &v) in x.col(c).iter().enumerate() {
            xt[i * p + c] = v;
        }
    }
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    let mut out = vec![0.0; n * p];
    const ROWS: usize = 256;
    out.par_chunks_mut(ROWS * p)
        .enumerate()
        .for_each(|(chunk, block)| {
            for (r, row) in block.chunks_mut(p).enumerate() {
                let j = chunk * ROWS + r;
                for k in cp[j]..cp[j + 1] {
                    let (s, src) = (v[k], &xt[ri[k] * p..ri[k] * p + p]);
                    for (o, &xv) in row.iter_mut().zip(src) {
                        *o += s * xv;
                    }
                }
            }
        });
    Mat::from_fn(n, p, |i, c| out[i * p + c])
}

/// `aᵀ b` for tall, thin `a` and `b` (n × k, n × p with n ≫ k, p): sequential products over
/// row chunks, one per rayon thread, summed. faer 0.24.4's parallel matmul took 10× longer than
/// its sequential one on this shape here (Lanczos reorthogonalisation on 98k rows, 208 × 16).
pub(crate) fn at_b(a: faer::MatRef<'_, Real>, b: faer::MatRef<'_, Real>) -> Mat<Real> {
    use rayon::prelude::*;
    let n = a.nrows();
    let threads = rayon::current_num_threads().max(1);
    let chunk = n.div_ceil(threads).max(1024);
    let starts: Vec<usize> = (0..n).step_by(chunk).collect();
    let partial: Vec<Mat<Real>> = starts
        .par_iter()
        .map(|&r0| {
            let rows = chunk.min(n - r0);
            let mut c = Mat::<Real>::zeros(a.ncols(), b.ncols());
            faer::linalg::matmul::matmul(
                c.as_mut(),
                faer::Accum::Replace,
                a.subrows(r0, rows).transpose(),
                b.subrows(r0, rows),
                1.0,
                faer::Par::Seq,
            );
            c
        })
        .collect();
    let mut out = Mat::<Real>::zeros(a.ncols(), b.ncols());
    for c in partial {
        out += c;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    /// A small symmetric matrix with a known pattern: a_ij = 1/(1 + i + j) on |i − j| ≤ 2.
    fn banded(n: usize) -> Sparse {
        let mut t = Vec::new();
        for j in 0..n {
            for i in j.saturating_sub(2)..(j + 3).min(n) {
                t.push(Triplet::new(i, j, 1.0 / (1.0 + i as Real + j as Real)));
            }
        }
        Sparse::try_new_from_triplets(n, n, &t).unwrap()
    }

    #[test]
    fn split_blocks_reassemble_the_matrix() {
        let a = banded(9);
        let d = to_dense(&a);
        let boundary = [7, 2, 4];
        let part = Partition::new(9, &boundary).unwrap();
        assert_eq!(part.interior, vec![0, 1, 3, 5, 6, 8]);
        let b = split(&a, &part);
        let (ii, ib) = (to_dense(&b.ii), to_dense(&b.ib));
        for (r, &i) in part.interior.iter().enumerate() {
            for (c, &j) in part.interior.iter().enumerate() {
                assert_eq!(ii[(r, c)], d[(i, j)]);
            }
            for (c, &j) in boundary.iter().enumerate() {
                assert_eq!(ib[(r, c)], d[(i, j)]);
            }
        }
        for (r, &i) in boundary.iter().enumerate() {
            for (c, &j) in boundary.iter().enumerate() {
                assert_eq!(b.bb[(r, c)], d[(i, j)]);
            }
        }
    }

    #[test]
    fn symmetric_product_equals_dense_product() {
        let a = banded(300);
        let x = Mat::<Real>::from_fn(300, 37, |i, j| ((i * 7 + j * 3) % 11) as Real - 5.0); // 3 panels
        let got = sym_spmm(&a, x.as_ref());
        let want = to_dense(&a) * &x;
        assert!((got - want).norm_max() < 1e-13);
    }

    #[test]
    fn asymmetry_is_detected() {
        let t = [
            Triplet::new(0, 1, 1.0),
            Triplet::new(1, 0, 1.0 + 1e-6),
            Triplet::new(0, 0, 3.0),
        ];
        let a = Sparse::try_new_from_triplets(2, 2, &t).unwrap();
        assert!(check_square(&a, 2, "A").is_err());
        assert!(check_square(&banded(5), 5, "A").is_ok());
        assert!(check_square(&banded(5), 4, "A").is_err());
    }
}
