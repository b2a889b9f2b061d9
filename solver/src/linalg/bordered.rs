//! A bordered block-diagonal matrix factorised block by block (the components of a reduced
//! brake model, coupled only through the contact rows).
//!
//! # Reference
//! With the positions of a square matrix split into diagonal blocks 1..p and a border W (the
//! multipliers, and any DOF that couples two blocks),
//! $$A = \begin{bmatrix} A_{11} & & & A_{1W} \\ & \ddots & & \vdots \\ & & A_{pp} & A_{pW} \\
//! A_{W1} & \cdots & A_{Wp} & A_{WW} \end{bmatrix},$$
//! block Gaussian elimination gives the Schur complement on the border
//! $$S = A_{WW} − \sum_i A_{Wi} A_{ii}^{-1} A_{iW},$$
//! and A x = r is solved by y_i = A_ii⁻¹ r_i, S x_W = r_W − Σ_i A_Wi y_i,
//! x_i = y_i − (A_ii⁻¹ A_iW) x_W. Each A_ii is factorised by a dense LU with partial pivoting
//! (the blocks in parallel), X_i = A_ii⁻¹ A_iW is kept for the back substitution (only the
//! border columns that block i touches), and S by a dense LU. For the BSQL saddle matrix the
//! blocks are cj M + B + K/cj of each component (symmetric positive definite for the paper's
//! matrix: no pivoting is lost by eliminating them first), and S = −s² G A⁻¹ (Gᵀ − D) plus the
//! open and compliant rows' diagonal (and the coupling DOFs' rows).
//!
//! Cost against the dense LU of the whole (N = Σ n_i + n_W): Σ_i (⅔ n_i³ + 2 n_i² w_i +
//! 2 n_i w_i r_i) + ⅔ n_W³ flops per factorisation (w_i, r_i: border columns and rows block i
//! touches) against ⅔ N³; per solve Σ_i 2 n_i² + 2 n_i (w_i + r_i) + 2 n_W² against 2 N².
//!
//! # Structure checked, not assumed
//! The partition is the caller's (found from the pattern of the constant matrices). Every
//! [`BorderedBlocks::factor`] first checks that the matrix it is given has no entry coupling
//! two different blocks (a friction damping C_f between pad and rotor has); if it does, it
//! returns `false` and the caller factorises the whole matrix instead.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use rayon::prelude::*;

use super::lu::DenseLu;
use crate::{Real, SolverError};

/// `block_of` value of a border position.
const BORDER: usize = usize::MAX;

/// One diagonal block with its factors and its coupling with the border.
struct Block {
    /// Positions of the block in the whole matrix, ascending.
    idx: Vec<usize>,
    /// LU of A_ii.
    lu: DenseLu,
    /// Border positions (indices into [`BorderedBlocks::border`]) of the columns A_iW that
    /// are non-zero.
    cols: Vec<usize>,
    /// Border positions of the rows A_Wi that are non-zero.
    rows: Vec<usize>,
    /// X_i = A_ii⁻¹ A_i,W[cols] (n_i × |cols|).
    x: Mat<Real>,
    /// A_W[rows],i (|rows| × n_i).
    awi: Mat<Real>,
    /// A_W[rows],i X_i (|rows| × |cols|).
    p: Mat<Real>,
    /// y_i of the last solve.
    y: Vec<Real>,
    /// x_W[cols] of the last solve.
    t: Vec<Real>,
}

impl Block {
    fn factor(
        &mut self,
        a: &Mat<Real>,
        border: &[usize],
        what: &'static str,
        t: Real,
    ) -> Result<(), SolverError> {
        let ni = self.idx.len();
        for (q, &j) in self.idx.iter().enumerate() {
            let src = a.col_as_slice(j);
            let dst = self.lu.a.col_as_slice_mut(q);
            for (p, &i) in self.idx.iter().enumerate() {
                dst[p] = src[i];
            }
        }
        self.lu.factor(what, t).map_err(|e| match e {
            SolverError::SingularMatrix {
                what,
                t,
                index,
                pivot,
                max_pivot,
            } => SolverError::SingularMatrix {
                what,
                t,
                index: self.idx[index],
                pivot,
                max_pivot,
            },
            SolverError::NonFinite {
                what,
                t,
                index,
                value,
            } => SolverError::NonFinite {
                what,
                t,
                index: self.idx[index],
                value,
            },
            e => e,
        })?;
        // The border columns and rows this block touches in this matrix.
        self.cols.clear();
        self.rows.clear();
        for (c, &w) in border.iter().enumerate() {
            let col = a.col_as_slice(w);
            if self.idx.iter().any(|&i| col[i] != 0.0) {
                self.cols.push(c);
            }
            if self.idx.iter().any(|&j| a[(w, j)] != 0.0) {
                self.rows.push(c);
            }
        }
        let (nc, nr) = (self.cols.len(), self.rows.len());
        self.x = Mat::from_fn(ni, nc, |p, c| a[(self.idx[p], border[self.cols[c]])]);
        self.lu.solve_mat(self.x.as_mut())?;
        self.awi = Mat::from_fn(nr, ni, |r, q| a[(border[self.rows[r]], self.idx[q])]);
        self.p = Mat::zeros(nr, nc);
        matmul(
            self.p.as_mut(),
            Accum::Replace,
            self.awi.as_ref(),
            self.x.as_ref(),
            1.0,
            Par::Seq,
        );
        self.t.resize(nc, 0.0);
        Ok(())
    }
}

/// A partition of the positions of a square matrix into diagonal blocks and a border, with the
/// factors of the last [`BorderedBlocks::factor`].
pub(crate) struct BorderedBlocks {
    n: usize,
    blocks: Vec<Block>,
    /// Border positions, ascending.
    border: Vec<usize>,
    /// Block of each position ([`BORDER`] for the border).
    block_of: Vec<usize>,
    /// LU of the Schur complement on the border.
    s: DenseLu,
    /// x_W of the last solve.
    xw: Vec<Real>,
}

impl BorderedBlocks {
    /// The partition of the positions 0..n: `block_of[i]` is the block of position i, or None
    /// for the border. Blocks are numbered by first appearance; empty ones are dropped.
    pub fn new(block_of: &[Option<usize>]) -> Self {
        let n = block_of.len();
        let mut ids: Vec<Option<usize>> = Vec::new();
        let mut idx: Vec<Vec<usize>> = Vec::new();
        let mut border = Vec::new();
        let mut of = vec![BORDER; n];
        for (i, b) in block_of.iter().enumerate() {
            match b {
                None => border.push(i),
                Some(b) => {
                    if *b >= ids.len() {
                        ids.resize(b + 1, None);
                    }
                    let k = *ids[*b].get_or_insert_with(|| {
                        idx.push(Vec::new());
                        idx.len() - 1
                    });
                    idx[k].push(i);
                    of[i] = k;
                }
            }
        }
        let blocks = idx
            .into_iter()
            .map(|idx| Block {
                lu: DenseLu::new(idx.len()),
                y: vec![0.0; idx.len()],
                idx,
                cols: Vec::new(),
                rows: Vec::new(),
                x: Mat::zeros(0, 0),
                awi: Mat::zeros(0, 0),
                p: Mat::zeros(0, 0),
                t: Vec::new(),
            })
            .collect();
        Self {
            n,
            blocks,
            s: DenseLu::new(border.len()),
            xw: vec![0.0; border.len()],
            border,
            block_of: of,
        }
    }

    /// Block sizes, and the border's.
    pub fn sizes(&self) -> (Vec<usize>, usize) {
        (
            self.blocks.iter().map(|b| b.idx.len()).collect(),
            self.border.len(),
        )
    }

    /// True when `a` (n × n) has no entry coupling two different blocks.
    pub fn fits(&self, a: &Mat<Real>) -> bool {
        (0..self.n).all(|j| {
            let bj = self.block_of[j];
            bj == BORDER || {
                let col = a.col_as_slice(j);
                self.block_of
                    .iter()
                    .zip(col)
                    .all(|(&bi, &x)| x == 0.0 || bi == bj || bi == BORDER)
            }
        })
    }

    /// Factorises `a` (n × n, left unchanged) block by block. Returns Ok(false), with nothing
    /// factorised, when `a` does not fit the partition ([`BorderedBlocks::fits`]). A singular
    /// block or Schur complement is an error naming the position (a block's) or the border
    /// position's matrix position.
    pub fn factor(
        &mut self,
        a: &Mat<Real>,
        what: &'static str,
        t: Real,
    ) -> Result<bool, SolverError> {
        if !self.fits(a) {
            return Ok(false);
        }
        let border = &self.border;
        self.blocks
            .par_iter_mut()
            .try_for_each(|b| b.factor(a, border, what, t))?;
        for (q, &j) in border.iter().enumerate() {
            let src = a.col_as_slice(j);
            let dst = self.s.a.col_as_slice_mut(q);
            for (p, &i) in border.iter().enumerate() {
                dst[p] = src[i];
            }
        }
        for b in &self.blocks {
            for (c, &cc) in b.cols.iter().enumerate() {
                let pc = b.p.col_as_slice(c);
                let sc = self.s.a.col_as_slice_mut(cc);
                for (r, &rr) in b.rows.iter().enumerate() {
                    sc[rr] -= pc[r];
                }
            }
        }
        self.s.factor(what, t).map_err(|e| match e {
            SolverError::SingularMatrix {
                what,
                t,
                index,
                pivot,
                max_pivot,
            } => SolverError::SingularMatrix {
                what,
                t,
                index: border[index],
                pivot,
                max_pivot,
            },
            e => e,
        })?;
        Ok(true)
    }

    /// Solves A x = r in place (after a successful [`BorderedBlocks::factor`]).
    pub fn solve(&mut self, x: &mut [Real]) -> Result<(), SolverError> {
        if x.len() != self.n {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side of the block solve",
                expected: self.n,
                got: x.len(),
            });
        }
        for (p, &w) in self.border.iter().enumerate() {
            self.xw[p] = x[w];
        }
        for b in &mut self.blocks {
            for (q, &i) in b.idx.iter().enumerate() {
                b.y[q] = x[i];
            }
            b.lu.solve(&mut b.y)?;
            for (q, &yq) in b.y.iter().enumerate() {
                if yq == 0.0 {
                    continue;
                }
                let col = b.awi.col_as_slice(q);
                for (r, &rr) in b.rows.iter().enumerate() {
                    self.xw[rr] -= col[r] * yq;
                }
            }
        }
        self.s.solve(&mut self.xw)?;
        for b in &mut self.blocks {
            for (c, &cc) in b.cols.iter().enumerate() {
                b.t[c] = self.xw[cc];
            }
            for (c, &tc) in b.t.iter().enumerate() {
                if tc == 0.0 {
                    continue;
                }
                let col = b.x.col_as_slice(c);
                for (y, &xc) in b.y.iter_mut().zip(col) {
                    *y -= xc * tc;
                }
            }
            for (q, &i) in b.idx.iter().enumerate() {
                x[i] = b.y[q];
            }
        }
        for (p, &w) in self.border.iter().enumerate() {
            x[w] = self.xw[p];
        }
        Ok(())
    }
}

/// Multiply–adds of one factorisation by blocks (sizes n_i, border columns w_i and rows r_i
/// each block touches, border size n_W) over those of the dense LU of the whole (see the
/// module docs).
pub(crate) fn cost_ratio(blocks: &[(usize, usize, usize)], n_border: usize) -> f64 {
    let cube = |x: usize| (x as f64).powi(3) / 3.0;
    let n_all = n_border + blocks.iter().map(|b| b.0).sum::<usize>();
    let by_blocks: f64 = blocks
        .iter()
        .map(|&(ni, wi, ri)| {
            let ni = ni as f64;
            cube(ni as usize) + ni * ni * wi as f64 + ni * (wi * ri) as f64
        })
        .sum::<f64>()
        + cube(n_border);
    by_blocks / cube(n_all).max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bordered matrix: blocks {0, 2, 5}, {1, 3}, {6}, border {4, 7} (interleaved), with a
    /// non-symmetric border and a zero border diagonal (a saddle point).
    fn bordered() -> (Mat<Real>, Vec<Option<usize>>) {
        let part = vec![
            Some(0),
            Some(1),
            Some(0),
            Some(1),
            None,
            Some(0),
            Some(2),
            None,
        ];
        let n = part.len();
        let mut s = 11u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as Real / (1u64 << 53) as Real - 0.5
        };
        let a = Mat::from_fn(n, n, |i, j| match (part[i], part[j]) {
            (Some(bi), Some(bj)) if bi != bj => 0.0,
            (Some(_), Some(_)) => {
                if i == j {
                    4.0 + rnd()
                } else {
                    rnd()
                }
            }
            (None, None) => 0.0,
            _ => rnd(),
        });
        (a, part)
    }

    #[test]
    fn block_solve_matches_the_dense_solve() {
        let (a, part) = bordered();
        let n = a.nrows();
        let mut blk = BorderedBlocks::new(&part);
        assert_eq!(blk.sizes(), (vec![3, 2, 1], 2));
        assert!(blk.factor(&a, "test", 0.0).unwrap());
        let mut dense = DenseLu::new(n);
        dense.a.copy_from(&a);
        dense.factor("dense", 0.0).unwrap();
        for k in 0..3 {
            let rhs: Vec<Real> = (0..n).map(|i| ((i + 3 * k) as Real * 0.9).cos()).collect();
            let mut want = rhs.clone();
            dense.solve(&mut want).unwrap();
            let mut got = rhs.clone();
            blk.solve(&mut got).unwrap();
            for i in 0..n {
                assert!(
                    (got[i] - want[i]).abs() <= 1e-13 * (1.0 + want[i].abs()),
                    "{i}: {} vs {}",
                    got[i],
                    want[i]
                );
            }
        }
    }

    #[test]
    fn a_matrix_coupling_two_blocks_is_refused() {
        let (mut a, part) = bordered();
        let mut blk = BorderedBlocks::new(&part);
        a[(3, 5)] = 1e-3; // block 1 row, block 0 column
        assert!(!blk.fits(&a));
        assert!(!blk.factor(&a, "test", 0.0).unwrap());
    }

    #[test]
    fn a_singular_block_is_reported_at_its_matrix_position() {
        let (mut a, part) = bordered();
        // Block 2 is position 6 alone: a zero diagonal makes it singular.
        a[(6, 6)] = 0.0;
        let mut blk = BorderedBlocks::new(&part);
        let err = blk.factor(&a, "test", 0.0).unwrap_err();
        assert!(
            matches!(err, SolverError::SingularMatrix { index: 6, .. }),
            "{err:?}"
        );
    }

    #[test]
    fn cost_ratio_of_two_equal_blocks_is_about_a_quarter() {
        // Two blocks of 500 with a border of 10 touched fully: ≈ 2·(1/8) of the whole.
        let r = cost_ratio(&[(500, 10, 10), (500, 10, 10)], 10);
        assert!(r > 0.24 && r < 0.27, "{r}");
    }
}
