//! Two-subdomain Cholesky: the top separator of a nested dissection splits A into D₁, D₂, S.
//!
//! # Derivation
//! In the order [D₁, D₂, S] the factor is L = [[L₁₁, 0, 0], [0, L₂₂, 0], [L_S1, L_S2, L_S]]
//! with L_S L_Sᵀ = A_SS − L_S1 L_S1ᵀ − L_S2 L_S2ᵀ. The bordered matrix
//! B_k = [[A_kk, A_kS], [A_Sk, A_SS]] (a principal submatrix of A, hence SPD) has the factor
//! F_k = [[L_kk, 0], [L_Sk, T_k]] with T_k T_kᵀ = A_SS − L_Sk L_Skᵀ. So
//! L_S L_Sᵀ = T₁T₁ᵀ + T₂T₂ᵀ − A_SS, from the two factors made independently.
//!
//! Solves reuse F_k: the forward substitution of F_k on [b_k; 0] gives [y_k; z_k] with
//! y_k = L_kk⁻¹ b_k and L_Sk y_k = −T_k z_k; the backward substitution of F_kᵀ on
//! [y_k; T_kᵀ x_S] gives x_k = L_kk⁻ᵀ (y_k − L_Skᵀ x_S).

use super::bordered::{fail, BorderedCholesky};
use crate::ordering::{CholeskyFill, DofPermutation};
use crate::{FeError, Real};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::SparseColMatRef;
use faer::{Accum, Mat, MatMut, Par, Side};
use serde::Serialize;
use std::time::Instant;

/// Sizes and costs of a [`SplitCholesky`].
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SplitStats {
    /// DOFs of the first subdomain, the second and the separator.
    pub sizes: [usize; 3],
    /// Stored entries of the two bordered factors and of the dense separator factor.
    pub factor_nnz: usize,
    /// Multiply–adds of the two sparse factorisations (Σ n_j² per factor) and of the dense
    /// separator (n_S³/3 + the two n_S³ products).
    pub factor_flops: Real,
    /// Seconds building the bordered matrices, factorising them, and the separator.
    pub build_s: Real,
    pub factor_s: Real,
    pub separator_s: Real,
}

/// Cholesky factor of an SPD matrix split at a separator, factorised and solved by two parallel
/// subdomain factors ([module docs](self)).
pub struct SplitCholesky {
    n: usize,
    /// Original indices of the separator.
    sep: Vec<usize>,
    parts: [BorderedCholesky; 2],
    /// L_S, the dense factor of the separator's Schur complement (lower).
    ls: Mat<Real>,
    stats: SplitStats,
}

impl SplitCholesky {
    /// Factorises the SPD matrix whose entries with row ≥ column are read from `a` (lower or
    /// full storage), ordered by `perm` (new → old), whose first `split[0]` positions are the
    /// first subdomain, the next `split[1]` the second, and the last `split[2]` the separator,
    /// no entry coupling the two subdomains (a nested dissection's top level:
    /// [`NestedDissectionStats::top_split_dofs`](crate::ordering::NestedDissectionStats)).
    ///
    /// Errors: sizes that do not add up, an entry coupling the subdomains, a matrix that is
    /// not positive definite.
    pub fn factorize(
        a: SparseColMatRef<'_, usize, Real>,
        perm: &DofPermutation,
        split: [usize; 3],
    ) -> Result<Self, FeError> {
        let n = a.ncols();
        let [n1, n2, ns] = split;
        if n1 + n2 + ns != n || perm.perm.len() != n || n1 == 0 || n2 == 0 {
            return Err(fail(
                "sizes",
                format!(
                    "split {split:?} of {n} DOFs (permutation of {})",
                    perm.perm.len()
                ),
            ));
        }
        let t0 = Instant::now();
        let sep: Vec<usize> = perm.perm[n1 + n2..].to_vec();
        // Which subdomain each original index is in (0, 1; 2 = separator).
        let mut side = vec![2u8; n];
        for &i in &perm.perm[..n1] {
            side[i] = 0;
        }
        for &i in &perm.perm[n1..n1 + n2] {
            side[i] = 1;
        }
        for j in 0..n {
            for &i in a.row_idx_of_col_raw(j) {
                if side[i] + side[j] == 1 {
                    return Err(fail(
                        "separator",
                        format!("entry ({i}, {j}) couples the two subdomains"),
                    ));
                }
            }
        }
        let build_s = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let (p1, p2) = rayon::join(
            || BorderedCholesky::factorize(a, &perm.perm[..n1], &sep),
            || BorderedCholesky::factorize(a, &perm.perm[n1..n1 + n2], &sep),
        );
        let (p1, p2) = (p1?, p2?);
        let factor_s = t1.elapsed().as_secs_f64();
        let t2 = Instant::now();
        // L_S L_Sᵀ = T₁T₁ᵀ + T₂T₂ᵀ − A_SS.
        let mut s = Mat::<Real>::zeros(ns, ns);
        let pos: std::collections::HashMap<usize, usize> =
            sep.iter().enumerate().map(|(k, &i)| (i, k)).collect();
        for (c, &j) in sep.iter().enumerate() {
            for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                if i >= j {
                    if let Some(&r) = pos.get(&i) {
                        s[(r, c)] -= v;
                        if r != c {
                            s[(c, r)] -= v;
                        }
                    }
                }
            }
        }
        let par = Par::rayon(0);
        for p in [&p1, &p2] {
            matmul(
                s.as_mut(),
                Accum::Add,
                p.trailing().as_ref(),
                p.trailing().transpose(),
                1.0,
                par,
            );
        }
        let ls = if ns > 0 {
            s.llt(Side::Lower)
                .map_err(|e| fail("separator Schur complement", e))?
                .L()
                .to_owned()
        } else {
            Mat::zeros(0, 0)
        };
        let separator_s = t2.elapsed().as_secs_f64();
        let fill: Vec<CholeskyFill> = [&p1, &p2].iter().map(|p| p.fill()).collect();
        let nsf = ns as Real;
        let stats = SplitStats {
            sizes: split,
            factor_nnz: fill.iter().map(|f| f.factor_nnz).sum::<usize>() + ns * (ns + 1) / 2,
            factor_flops: fill.iter().map(|f| f.factor_flops).sum::<Real>()
                + nsf * nsf * nsf * (1.0 / 3.0 + 2.0),
            build_s,
            factor_s,
            separator_s,
        };
        Ok(SplitCholesky {
            n,
            sep,
            parts: [p1, p2],
            ls,
            stats,
        })
    }

    /// Sizes, fill and timings.
    pub fn stats(&self) -> &SplitStats {
        &self.stats
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Overwrites `rhs` (n × k, original order) with A⁻¹ rhs; the two subdomains' substitutions
    /// run in parallel.
    pub fn solve_in_place(&self, mut rhs: MatMut<'_, Real>) {
        let k = rhs.ncols();
        let ns = self.sep.len();
        let gather = |p: &BorderedCholesky, rhs: &MatMut<'_, Real>| {
            let mut z = Mat::<Real>::zeros(p.rows().len(), k);
            for c in 0..k {
                let src = rhs.as_ref().col(c);
                let dst = z.col_as_slice_mut(c);
                for (d, &i) in dst[..p.n_own()].iter_mut().zip(p.rows()) {
                    *d = src[i];
                }
            }
            z
        };
        let (mut z1, mut z2) = (gather(&self.parts[0], &rhs), gather(&self.parts[1], &rhs));
        rayon::join(
            || self.parts[0].substitute(z1.as_mut(), false),
            || self.parts[1].substitute(z2.as_mut(), false),
        );
        // b_S + T₁ z₁ + T₂ z₂, then L_S⁻ᵀ L_S⁻¹.
        let mut xs = Mat::<Real>::from_fn(ns, k, |r, c| rhs[(self.sep[r], c)]);
        for (p, z) in [(&self.parts[0], &z1), (&self.parts[1], &z2)] {
            matmul(
                xs.as_mut(),
                Accum::Add,
                p.trailing().as_ref(),
                z.as_ref().subrows(p.n_own(), ns),
                1.0,
                Par::Seq,
            );
        }
        solve_lower_triangular_in_place(self.ls.as_ref(), xs.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.ls.transpose(), xs.as_mut(), Par::Seq);
        for (p, z) in [(&self.parts[0], &mut z1), (&self.parts[1], &mut z2)] {
            matmul(
                z.as_mut().subrows_mut(p.n_own(), ns),
                Accum::Replace,
                p.trailing().transpose(),
                xs.as_ref(),
                1.0,
                Par::Seq,
            );
        }
        rayon::join(
            || self.parts[0].substitute(z1.as_mut(), true),
            || self.parts[1].substitute(z2.as_mut(), true),
        );
        for c in 0..k {
            let mut dst = rhs.as_mut().col_mut(c);
            for p_z in [(&self.parts[0], &z1), (&self.parts[1], &z2)] {
                let (p, z) = p_z;
                let src = z.col_as_slice(c);
                for (&i, &v) in p.rows()[..p.n_own()].iter().zip(src) {
                    dst[i] = v;
                }
            }
            for (r, &i) in self.sep.iter().enumerate() {
                dst[i] = xs[(r, c)];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ordering::nested_dissection;
    use crate::NestedDissectionOptions;
    use faer::sparse::{SparseColMat, Triplet};

    /// 3D 7-point Laplacian + shift on an nx × ny × nz grid (SPD), with its node coordinates.
    fn grid(nx: usize, ny: usize, nz: usize) -> (SparseColMat<usize, Real>, Vec<[Real; 3]>) {
        let id = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
        let n = nx * ny * nz;
        let mut t = Vec::new();
        let mut xyz = vec![[0.0; 3]; n];
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let p = id(i, j, k);
                    xyz[p] = [i as Real, j as Real * 1.1, k as Real * 0.9];
                    t.push(Triplet::new(p, p, 6.2 + (p % 7) as Real * 0.01));
                    for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        let (a, b, c) = (i + di, j + dj, k + dk);
                        if a < nx && b < ny && c < nz {
                            let q = id(a, b, c);
                            t.push(Triplet::new(p, q, -1.0));
                            t.push(Triplet::new(q, p, -1.0));
                        }
                    }
                }
            }
        }
        (SparseColMat::try_new_from_triplets(n, n, &t).unwrap(), xyz)
    }

    #[test]
    fn solves_like_the_matrix_it_factorised() {
        // Reference: the residual ‖A x − b‖ of the solution itself (A applied directly).
        let (a, xyz) = grid(14, 9, 7);
        let n = a.nrows();
        let opts = NestedDissectionOptions {
            leaf_nodes: 8,
            ..Default::default()
        };
        let (perm, nd) = nested_dissection(a.symbolic(), &xyz, &opts).unwrap();
        let f = SplitCholesky::factorize(a.as_ref(), &perm, nd.top_split_dofs).unwrap();
        assert!(
            nd.top_split_dofs.iter().all(|&s| s > 0),
            "{:?}",
            nd.top_split_dofs
        );
        let b = Mat::<Real>::from_fn(n, 3, |i, j| ((i * 13 + j * 7) % 11) as Real - 5.0);
        let mut x = b.clone();
        f.solve_in_place(x.as_mut());
        let mut r = b.clone();
        faer::sparse::linalg::matmul::sparse_dense_matmul(
            r.as_mut(),
            Accum::Add,
            a.as_ref(),
            x.as_ref(),
            -1.0,
            Par::Seq,
        );
        let rn = r.norm_max() / b.norm_max();
        assert!(rn < 1e-12, "relative residual {rn:e}");
    }

    #[test]
    fn refuses_a_split_that_is_not_a_separator() {
        let (a, _) = grid(6, 5, 4);
        let n = a.nrows();
        let perm = DofPermutation::from_order((0..n).collect()).unwrap();
        // Natural order cut in three consecutive slabs: the first two touch.
        let e = SplitCholesky::factorize(a.as_ref(), &perm, [40, 40, n - 80]);
        assert!(
            matches!(e, Err(FeError::Factorisation { .. })),
            "{:?}",
            e.err()
        );
    }
}
