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

use crate::ordering::{CholeskyFill, DofPermutation};
use crate::{FeError, Real};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Accum, Conj, Mat, MatMut, Par, Side, Spec};
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

struct Part {
    /// New → original index of the bordered matrix's rows: D_k then S.
    rows: Vec<usize>,
    n_own: usize,
    sym: SymbolicCholesky<usize>,
    vals: Vec<Real>,
    /// T_k, the factor's trailing n_S × n_S block (lower).
    t: Mat<Real>,
}

/// Cholesky factor of an SPD matrix split at a separator, factorised and solved by two parallel
/// subdomain factors ([module docs](self)).
pub struct SplitCholesky {
    n: usize,
    /// Original indices of the separator.
    sep: Vec<usize>,
    parts: [Part; 2],
    /// L_S, the dense factor of the separator's Schur complement (lower).
    ls: Mat<Real>,
    stats: SplitStats,
}

fn fail(what: &str, e: impl std::fmt::Debug) -> FeError {
    FeError::Factorisation {
        what: format!("split Cholesky: {what}"),
        reason: format!("{e:?}"),
    }
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
        let rows = |range: std::ops::Range<usize>| -> Vec<usize> {
            perm.perm[range].iter().chain(&sep).copied().collect()
        };
        let (r1, r2) = (rows(0..n1), rows(n1..n1 + n2));
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
        let (b1, b2) = rayon::join(|| bordered(a, &r1), || bordered(a, &r2));
        let build_s = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let (p1, p2) = rayon::join(
            || factor_part(b1, r1, n1, ns),
            || factor_part(b2, r2, n2, ns),
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
                p.t.as_ref(),
                p.t.transpose(),
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
        let fill: Vec<CholeskyFill> = [&p1, &p2]
            .iter()
            .map(|p| CholeskyFill::of(&p.sym))
            .collect();
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
        let gather = |p: &Part, rhs: &MatMut<'_, Real>| {
            let mut z = Mat::<Real>::zeros(p.rows.len(), k);
            for c in 0..k {
                let src = rhs.as_ref().col(c);
                let dst = z.col_as_slice_mut(c);
                for (d, &i) in dst[..p.n_own].iter_mut().zip(&p.rows) {
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
                p.t.as_ref(),
                z.as_ref().subrows(p.n_own, ns),
                1.0,
                Par::Seq,
            );
        }
        solve_lower_triangular_in_place(self.ls.as_ref(), xs.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.ls.transpose(), xs.as_mut(), Par::Seq);
        for (p, z) in [(&self.parts[0], &mut z1), (&self.parts[1], &mut z2)] {
            matmul(
                z.as_mut().subrows_mut(p.n_own, ns),
                Accum::Replace,
                p.t.transpose(),
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
                for (&i, &v) in p.rows[..p.n_own].iter().zip(src) {
                    dst[i] = v;
                }
            }
            for (r, &i) in self.sep.iter().enumerate() {
                dst[i] = xs[(r, c)];
            }
        }
    }
}

impl Part {
    /// Forward (L) or backward (Lᵀ, `transpose`) substitution with the bordered factor, in place.
    fn substitute(&self, z: MatMut<'_, Real>, transpose: bool) {
        let SymbolicCholeskyRaw::Supernodal(s) = self.sym.raw() else {
            unreachable!("split Cholesky parts are supernodal")
        };
        let mut buf = MemBuffer::new(s.solve_in_place_scratch::<Real>(z.ncols(), Par::Seq));
        let f = SupernodalLltRef::new(s, &self.vals);
        let stack = MemStack::new(&mut buf);
        if transpose {
            f.l_transpose_solve_with_conj(Conj::No, z, Par::Seq, stack);
        } else {
            f.l_solve_with_conj(Conj::No, z, Par::Seq, stack);
        }
    }
}

/// The lower triangle of A restricted to `rows` (new → original), in that order.
fn bordered(a: SparseColMatRef<'_, usize, Real>, rows: &[usize]) -> SparseColMat<usize, Real> {
    let m = rows.len();
    let mut local = vec![usize::MAX; a.ncols()];
    for (l, &i) in rows.iter().enumerate() {
        local[i] = l;
    }
    // Entry (i ≥ j) of A goes to column min(li, lj), row max(li, lj).
    let mut count = vec![0usize; m + 1];
    for (lj, &j) in rows.iter().enumerate() {
        for &i in a.row_idx_of_col_raw(j) {
            let li = local[i];
            if i >= j && li != usize::MAX {
                count[li.min(lj) + 1] += 1;
            }
        }
    }
    for c in 0..m {
        count[c + 1] += count[c];
    }
    let mut fill = count.clone();
    let mut ri = vec![0usize; count[m]];
    let mut rv = vec![0.0; count[m]];
    for (lj, &j) in rows.iter().enumerate() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            let li = local[i];
            if i >= j && li != usize::MAX {
                let (r, c) = (li.max(lj), li.min(lj));
                ri[fill[c]] = r;
                rv[fill[c]] = v;
                fill[c] += 1;
            }
        }
    }
    // Sort each column by row.
    for c in 0..m {
        let (s, e) = (count[c], count[c + 1]);
        let mut idx: Vec<usize> = (s..e).collect();
        idx.sort_unstable_by_key(|&p| ri[p]);
        let (r, v): (Vec<usize>, Vec<Real>) = idx.iter().map(|&p| (ri[p], rv[p])).unzip();
        ri[s..e].copy_from_slice(&r);
        rv[s..e].copy_from_slice(&v);
    }
    SparseColMat::new(SymbolicSparseColMat::new_checked(m, m, count, None, ri), rv)
}

fn factor_part(
    b: SparseColMat<usize, Real>,
    rows: Vec<usize>,
    n_own: usize,
    ns: usize,
) -> Result<Part, FeError> {
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    // An explicit identity permutation: faer 0.24's `SymmetricOrdering::Identity` skips the
    // conversion to the upper triangle its symbolic analysis reads, and ignores `side`.
    let id: Vec<usize> = (0..b.ncols()).collect();
    let ord = SymmetricOrdering::Custom(PermRef::new_checked(&id, &id, b.ncols()));
    let sym = factorize_symbolic_cholesky(b.symbolic(), Side::Lower, ord, params)
        .map_err(|e| fail("symbolic", e))?;
    drop(id);
    let mut vals = vec![0.0; sym.len_val()];
    let par = Par::Seq;
    let mut buf =
        MemBuffer::try_new(sym.factorize_numeric_llt_scratch::<Real>(par, Spec::default()))
            .map_err(|e| fail("workspace", e))?;
    sym.factorize_numeric_llt(
        &mut vals,
        b.as_ref(),
        Side::Lower,
        LltRegularization::default(),
        par,
        MemStack::new(&mut buf),
        Spec::default(),
    )
    .map_err(|e| fail("subdomain (not positive definite)", e))?;
    drop(b);
    // T_k: the factor's entries in rows and columns ≥ n_own.
    let SymbolicCholeskyRaw::Supernodal(s) = sym.raw() else {
        unreachable!("forced supernodal")
    };
    let mut t = Mat::<Real>::zeros(ns, ns);
    let f = SupernodalLltRef::new(s, &vals);
    for k in 0..s.n_supernodes() {
        let node = f.supernode(k);
        let (start, mat, pattern) = (node.start(), node.val(), node.pattern());
        let width = mat.ncols();
        if start + width <= n_own {
            continue;
        }
        for c in 0..width {
            let col = start + c;
            if col < n_own {
                continue;
            }
            for r in c..width {
                t[(start + r - n_own, col - n_own)] = mat[(r, c)];
            }
            for (q, &row) in pattern.iter().enumerate() {
                t[(row - n_own, col - n_own)] = mat[(width + q, c)];
            }
        }
    }
    Ok(Part {
        rows,
        n_own,
        sym,
        vals,
        t,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ordering::nested_dissection;
    use crate::NestedDissectionOptions;
    use faer::sparse::Triplet;

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
