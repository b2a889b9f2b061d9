//! Cholesky factor of a bordered principal submatrix B = [[A_oo, A_ob], [A_bo, A_bb]] of an SPD
//! matrix: the "own" rows first (in the given order), the border last.
//!
//! # Derivation
//! F = [[L, 0], [X, T]] with L Lᵀ = A_oo, X = A_bo L⁻ᵀ and T Tᵀ = A_bb − X Xᵀ, the Schur
//! complement of the own block on the border (the condensed stiffness when A is a stiffness).
//! The forward substitution of F on [b; 0] gives [L⁻¹b; z]; the backward substitution of Fᵀ on
//! [y; 0] gives [L⁻ᵀy; 0], so A_oo⁻¹ is applied with the same factor as B⁻¹.

use crate::ordering::CholeskyFill;
use crate::{FeError, Real};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Mat, MatMut, Par, Side, Spec};

pub(crate) fn fail(what: &str, e: impl std::fmt::Debug) -> FeError {
    FeError::Factorisation {
        what: format!("bordered Cholesky: {what}"),
        reason: format!("{e:?}"),
    }
}

/// The factor F of a bordered submatrix ([module docs](self)).
pub struct BorderedCholesky {
    /// Original indices of B's rows: the own rows, then the border.
    rows: Vec<usize>,
    n_own: usize,
    sym: SymbolicCholesky<usize>,
    vals: Vec<Real>,
    /// T, the factor's trailing border × border block (lower).
    t: Mat<Real>,
}

impl BorderedCholesky {
    /// Factorises A restricted to `own` then `border` (original indices, in that order; the
    /// entries with row ≥ column are read from `a`, lower or full storage), with faer's
    /// sequential supernodal kernels.
    ///
    /// Errors: a repeated or out-of-range index, a submatrix that is not positive definite.
    pub fn factorize(
        a: SparseColMatRef<'_, usize, Real>,
        own: &[usize],
        border: &[usize],
    ) -> Result<Self, FeError> {
        let rows: Vec<usize> = own.iter().chain(border).copied().collect();
        let b = bordered(a, &rows)?;
        let n_own = own.len();
        let ns = border.len();
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
        .map_err(|e| fail("not positive definite", e))?;
        drop(b);
        // T: the factor's entries in rows and columns ≥ n_own.
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
        Ok(BorderedCholesky {
            rows,
            n_own,
            sym,
            vals,
            t,
        })
    }

    /// Original indices of the own rows, then of the border.
    pub fn rows(&self) -> &[usize] {
        &self.rows
    }

    /// Number of own rows.
    pub fn n_own(&self) -> usize {
        self.n_own
    }

    /// T (border × border, lower): T Tᵀ is the Schur complement A_bb − A_bo A_oo⁻¹ A_ob.
    pub fn trailing(&self) -> &Mat<Real> {
        &self.t
    }

    /// Fill and cost of the factor.
    pub fn fill(&self) -> CholeskyFill {
        CholeskyFill::of(&self.sym)
    }

    /// Forward (L) or backward (Lᵀ, `transpose`) substitution with F on a vector block in
    /// B's row order, in place.
    pub fn substitute(&self, z: MatMut<'_, Real>, transpose: bool) {
        let SymbolicCholeskyRaw::Supernodal(s) = self.sym.raw() else {
            unreachable!("forced supernodal")
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

    /// x ← A_oo⁻¹ x for x with the own rows only (in `rows()` order), sequential.
    pub fn solve_own(&self, mut x: MatMut<'_, Real>) {
        let (k, ns) = (x.ncols(), self.t.nrows());
        let mut z = Mat::<Real>::zeros(self.n_own + ns, k);
        z.as_mut().subrows_mut(0, self.n_own).copy_from(x.as_ref());
        self.substitute(z.as_mut(), false);
        z.as_mut().subrows_mut(self.n_own, ns).fill(0.0);
        self.substitute(z.as_mut(), true);
        x.copy_from(z.as_ref().subrows(0, self.n_own));
    }

    /// x ← B⁻¹ x for x over all of B's rows (in `rows()` order), sequential.
    pub fn solve_all(&self, x: MatMut<'_, Real>) {
        let mut x = x;
        self.substitute(x.as_mut(), false);
        self.substitute(x.as_mut(), true);
    }
}

/// The lower triangle of A restricted to `rows` (new → original), in that order.
fn bordered(
    a: SparseColMatRef<'_, usize, Real>,
    rows: &[usize],
) -> Result<SparseColMat<usize, Real>, FeError> {
    let m = rows.len();
    let mut local = vec![usize::MAX; a.ncols()];
    for (l, &i) in rows.iter().enumerate() {
        if i >= a.ncols() || local[i] != usize::MAX {
            return Err(fail("rows", format!("index {i} repeated or out of range")));
        }
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
    let mut idx = Vec::new();
    for c in 0..m {
        let (s, e) = (count[c], count[c + 1]);
        idx.clear();
        idx.extend(s..e);
        idx.sort_unstable_by_key(|&p| ri[p]);
        let (r, v): (Vec<usize>, Vec<Real>) = idx.iter().map(|&p| (ri[p], rv[p])).unzip();
        ri[s..e].copy_from_slice(&r);
        rv[s..e].copy_from_slice(&v);
    }
    Ok(SparseColMat::new(
        SymbolicSparseColMat::new_checked(m, m, count, None, ri),
        rv,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::Solve;
    use faer::sparse::Triplet;

    #[test]
    fn own_solve_and_trailing_block_match_dense_algebra() {
        // Reference: dense solves and the dense Schur complement of the same SPD matrix
        // (a 2-D 5-point Laplacian plus a diagonal shift on a 9 × 7 grid).
        let (nx, ny) = (9, 7);
        let n = nx * ny;
        let mut t = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let p = j * nx + i;
                t.push(Triplet::new(p, p, 4.3 + (p % 5) as Real * 0.1));
                if i + 1 < nx {
                    t.push(Triplet::new(p, p + 1, -1.0));
                    t.push(Triplet::new(p + 1, p, -1.0));
                }
                if j + 1 < ny {
                    t.push(Triplet::new(p, p + nx, -1.0));
                    t.push(Triplet::new(p + nx, p, -1.0));
                }
            }
        }
        let a = SparseColMat::<usize, Real>::try_new_from_triplets(n, n, &t).unwrap();
        let dense = a.to_dense();
        // Own: the first three grid rows, scrambled; border: the fourth row.
        let mut own: Vec<usize> = (0..3 * nx).rev().collect();
        own.swap(2, 11);
        let border: Vec<usize> = (3 * nx..4 * nx).collect();
        let f = BorderedCholesky::factorize(a.as_ref(), &own, &border).unwrap();
        let pick = |r: &[usize], c: &[usize]| {
            Mat::<Real>::from_fn(r.len(), c.len(), |i, j| dense[(r[i], c[j])])
        };
        let aoo = pick(&own, &own);
        let b = Mat::<Real>::from_fn(own.len(), 2, |i, j| (i as Real + 1.0) * (j as Real - 0.5));
        let mut x = b.clone();
        f.solve_own(x.as_mut());
        let r = &aoo * &x - &b;
        assert!(r.norm_max() < 1e-12, "own residual {:e}", r.norm_max());
        let schur = pick(&border, &border)
            - pick(&border, &own) * aoo.llt(Side::Lower).unwrap().solve(pick(&own, &border));
        let tt = f.trailing() * f.trailing().transpose();
        assert!(
            (&tt - &schur).norm_max() < 1e-12,
            "{:e}",
            (&tt - &schur).norm_max()
        );
        // Whole bordered solve.
        let all: Vec<usize> = own.iter().chain(&border).copied().collect();
        let ball = Mat::<Real>::from_fn(all.len(), 1, |i, _| (i % 4) as Real);
        let mut y = ball.clone();
        f.solve_all(y.as_mut());
        let r = pick(&all, &all) * &y - &ball;
        assert!(r.norm_max() < 1e-12);
        // A repeated index is an error.
        assert!(BorderedCholesky::factorize(a.as_ref(), &[0, 1], &[1]).is_err());
    }
}
