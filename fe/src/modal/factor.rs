//! The shifted matrix K − σM and its factorisation, used as the operator (K − σM)⁻¹.

use super::options::FactorKind;
use crate::cholesky::{SplitCholesky, SplitStats};
use crate::ordering::{CholeskyFill, DofPermutation};
use crate::{FeError, Real};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side, Spec};

/// A factorisation of K − σM.
pub(crate) enum Factor {
    /// Two subdomains and the top separator, factorised and solved in parallel.
    Split(Box<SplitCholesky>),
    Llt(SymbolicCholesky<usize>, Vec<Real>),
    Ldlt(SymbolicCholesky<usize>, Vec<Real>),
    Lu(Lu<usize, Real>),
}

pub(crate) struct Factored {
    pub factor: Factor,
    pub kind: FactorKind,
    pub fallback_reason: Option<String>,
    pub factor_nnz: usize,
    pub supernodal: bool,
    pub factor_flops: Real,
    pub factorisations: usize,
    pub split: Option<SplitStats>,
}

/// K − σM (lower triangle only if `lower`), merging the sorted columns of K and M.
pub fn shifted(
    k: SparseColMatRef<'_, usize, Real>,
    m: SparseColMatRef<'_, usize, Real>,
    sigma: Real,
    lower: bool,
) -> SparseColMat<usize, Real> {
    let n = k.ncols();
    let mut ptr = Vec::with_capacity(n + 1);
    ptr.push(0);
    let mut rows = Vec::with_capacity(k.compute_nnz() / if lower { 2 } else { 1 } + n);
    let mut vals = Vec::with_capacity(rows.capacity());
    for j in 0..n {
        let (kr, kv) = (k.row_idx_of_col_raw(j), k.val_of_col(j));
        let (mr, mv) = (m.row_idx_of_col_raw(j), m.val_of_col(j));
        let (mut p, mut q) = (0, 0);
        while p < kr.len() || q < mr.len() {
            let rk = kr.get(p).copied().unwrap_or(usize::MAX);
            let rm = mr.get(q).copied().unwrap_or(usize::MAX);
            let (r, v) = if rk == rm {
                p += 1;
                q += 1;
                (rk, kv[p - 1] - sigma * mv[q - 1])
            } else if rk < rm {
                p += 1;
                (rk, kv[p - 1])
            } else {
                q += 1;
                (rm, -sigma * mv[q - 1])
            };
            if !lower || r >= j {
                rows.push(r);
                vals.push(v);
            }
        }
        ptr.push(rows.len());
    }
    SparseColMat::new(
        SymbolicSparseColMat::new_checked(n, n, ptr, None, rows),
        vals,
    )
}

/// Factorises K − σM: with a nested-dissection `perm` whose top level splits the DOFs
/// (`split` = its [first half, second half, separator] sizes), the [`SplitCholesky`];
/// otherwise, or when that fails, Cholesky, else LDLᵀ on the same symbolic structure, else LU.
/// `perm` is the fill-reducing ordering (AMD when `None`).
pub(crate) fn factorise(
    k: SparseColMatRef<'_, usize, Real>,
    m: SparseColMatRef<'_, usize, Real>,
    sigma: Real,
    perm: Option<&DofPermutation>,
    split: Option<[usize; 3]>,
) -> Result<Factored, FeError> {
    let par = Par::rayon(0);
    let a = shifted(k, m, sigma, true);
    let mut split_failed = None;
    if let (Some(p), Some(sizes)) = (perm, split) {
        match SplitCholesky::factorize(a.as_ref(), p, sizes) {
            Ok(f) => {
                let st = f.stats().clone();
                return Ok(Factored {
                    factor: Factor::Split(Box::new(f)),
                    kind: FactorKind::Llt,
                    fallback_reason: None,
                    factor_nnz: st.factor_nnz,
                    supernodal: true,
                    factor_flops: st.factor_flops,
                    factorisations: 1,
                    split: Some(st),
                });
            }
            Err(e) => split_failed = Some(e.to_string()),
        }
    }
    let fail = |what: &str, e: String| FeError::Factorisation {
        what: format!("{what} of K - sigma M (sigma = {sigma:e})"),
        reason: e,
    };
    let ordering = match perm {
        Some(p) => SymmetricOrdering::Custom(PermRef::new_checked(&p.perm, &p.perm_inv, a.ncols())),
        None => SymmetricOrdering::Amd,
    };
    let sym = factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default())
        .map_err(|e| fail("symbolic Cholesky", format!("{e:?}")))?;
    let len = sym.len_val();
    let fill = CholeskyFill::of(&sym);
    let (supernodal, factor_flops) = (fill.supernodal, fill.factor_flops);
    let mut vals = vec![0.0; len];
    let llt = {
        let mut buf =
            MemBuffer::try_new(sym.factorize_numeric_llt_scratch::<Real>(par, Spec::default()))
                .map_err(|e| fail("Cholesky workspace", format!("{e:?}")))?;
        sym.factorize_numeric_llt(
            &mut vals,
            a.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut buf),
            Spec::default(),
        )
        .map(|_| ())
    };
    let llt_err = match llt {
        Ok(()) => {
            return Ok(Factored {
                factor: Factor::Llt(sym, vals),
                kind: FactorKind::Llt,
                fallback_reason: None,
                factor_nnz: len,
                supernodal,
                factor_flops,
                factorisations: 1,
                split: None,
            })
        }
        Err(e) => format!(
            "Cholesky failed ({e:?}): K - sigma M is not positive definite{}",
            split_failed.map_or(String::new(), |s| format!(" (split factor: {s})"))
        ),
    };
    let ldlt = {
        let mut buf =
            MemBuffer::try_new(sym.factorize_numeric_ldlt_scratch::<Real>(par, Spec::default()))
                .map_err(|e| fail("LDLT workspace", format!("{e:?}")))?;
        sym.factorize_numeric_ldlt(
            &mut vals,
            a.as_ref(),
            Side::Lower,
            LdltRegularization::default(),
            par,
            MemStack::new(&mut buf),
            Spec::default(),
        )
        .map(|_| ())
    };
    if ldlt.is_ok() && vals.iter().all(|v| v.is_finite()) {
        return Ok(Factored {
            factor: Factor::Ldlt(sym, vals),
            kind: FactorKind::Ldlt,
            fallback_reason: Some(llt_err),
            factor_nnz: len,
            supernodal,
            factor_flops,
            factorisations: 2,
            split: None,
        });
    }
    let full = shifted(k, m, sigma, false);
    let lu = full
        .sp_lu()
        .map_err(|e| fail("LU (after Cholesky and LDLT failed)", format!("{e:?}")))?;
    Ok(Factored {
        factor: Factor::Lu(lu),
        kind: FactorKind::Lu,
        fallback_reason: Some(format!("{llt_err}; LDLT failed too: {ldlt:?}")),
        factor_nnz: 0,
        supernodal: false,
        factor_flops: 0.0,
        factorisations: 3,
        split: None,
    })
}

impl Factor {
    /// Solves (K − σM) X = B in place for a block B, its columns split evenly over the rayon
    /// threads (each thread one pass over the factor with its columns).
    pub fn solve_block(&self, rhs: MatMut<'_, Real>) {
        if let Factor::Split(f) = self {
            return f.solve_in_place(rhs);
        }
        let threads = rayon::current_num_threads().max(1);
        let chunk = rhs.ncols().div_ceil(threads).max(1);
        if chunk >= rhs.ncols() {
            return self.solve_in_place(rhs);
        }
        use rayon::prelude::*;
        rhs.par_col_chunks_mut(chunk)
            .for_each(|c| self.solve_in_place(c));
    }

    /// Solves (K − σM) X = B in place, B ← X.
    pub fn solve_in_place(&self, rhs: MatMut<'_, Real>) {
        // Sequential: the supernodal solve is a chain of small memory-bound products per
        // supernode, and faer's fork-join per supernode cost 30-70 % more wall time than
        // sequential solves with 8 right-hand sides on the shared 2-core machine.
        let par = Par::Seq;
        let ncols = rhs.ncols();
        match self {
            Factor::Split(f) => f.solve_in_place(rhs),
            Factor::Llt(sym, vals) => {
                let mut buf = MemBuffer::new(sym.solve_in_place_scratch::<Real>(ncols, par));
                LltRef::new(sym, vals).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    par,
                    MemStack::new(&mut buf),
                );
            }
            Factor::Ldlt(sym, vals) => {
                let mut buf = MemBuffer::new(sym.solve_in_place_scratch::<Real>(ncols, par));
                LdltRef::new(sym, vals).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    par,
                    MemStack::new(&mut buf),
                );
            }
            Factor::Lu(lu) => lu.solve_in_place(rhs),
        }
    }
}
