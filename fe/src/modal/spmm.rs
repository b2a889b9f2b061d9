//! Y = A X for a sparse symmetric A stored with both triangles, X a dense block.
//!
//! faer 0.24's `sparse_dense_matmul` is sequential and reads A once per column of X. Here A is
//! read once per 8 columns, in parallel over rows: by symmetry row j of A is column j, so
//! y[j, :] = Σ_i a_ij x[i, :] gathers from a row-major copy of the block.

use crate::Real;
use faer::sparse::SparseColMatRef;
use faer::{MatMut, MatRef};
use rayon::prelude::*;

/// Columns of X handled per pass over A.
const W: usize = 8;
/// Rows per parallel task.
const ROWS: usize = 2048;

/// `y ← A x` with A symmetric (full storage). `y` and `x` are n × k.
pub(crate) fn sym_matmul(
    a: SparseColMatRef<'_, usize, Real>,
    x: MatRef<'_, Real>,
    mut y: MatMut<'_, Real>,
) {
    let n = a.ncols();
    debug_assert!(x.nrows() == n && y.nrows() == n && x.ncols() == y.ncols());
    let mut xt = vec![0.0; n * W];
    let mut yt = vec![0.0; n * W];
    for k0 in (0..x.ncols()).step_by(W) {
        let w = (x.ncols() - k0).min(W);
        for k in 0..w {
            let col = x.col(k0 + k);
            for i in 0..n {
                xt[i * W + k] = col[i];
            }
        }
        yt.par_chunks_mut(ROWS * W)
            .enumerate()
            .for_each(|(c, out)| {
                let j0 = c * ROWS;
                for (jj, yrow) in out.chunks_exact_mut(W).enumerate() {
                    let j = j0 + jj;
                    let mut acc = [0.0; W];
                    for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                        let xr = &xt[i * W..i * W + W];
                        for k in 0..W {
                            acc[k] += v * xr[k];
                        }
                    }
                    yrow.copy_from_slice(&acc);
                }
            });
        for k in 0..w {
            let mut col = y.as_mut().col_mut(k0 + k);
            for i in 0..n {
                col[i] = yt[i * W + k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::linalg::matmul::sparse_dense_matmul;
    use faer::sparse::{SparseColMat, Triplet};
    use faer::{Accum, Mat, Par};

    #[test]
    fn matches_faer_product_with_a_partial_column_chunk() {
        // Symmetric tridiagonal-plus-corner matrix, 11 columns (one full chunk of 8 + 3).
        let n = 5000;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 2.0 + i as f64 * 1e-3));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        t.push(Triplet::new(0, n - 1, 0.5));
        t.push(Triplet::new(n - 1, 0, 0.5));
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        let x = Mat::<f64>::from_fn(n, 11, |i, j| ((i * 7 + j * 13) % 17) as f64 - 8.0);
        let mut y = Mat::<f64>::zeros(n, 11);
        sym_matmul(a.as_ref(), x.as_ref(), y.as_mut());
        let mut r = Mat::<f64>::zeros(n, 11);
        sparse_dense_matmul(
            r.as_mut(),
            Accum::Replace,
            a.as_ref(),
            x.as_ref(),
            1.0,
            Par::Seq,
        );
        for j in 0..11 {
            for i in 0..n {
                assert!((y[(i, j)] - r[(i, j)]).abs() <= 1e-12 * r[(i, j)].abs().max(1.0));
            }
        }
    }
}
