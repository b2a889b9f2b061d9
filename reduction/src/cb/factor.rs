//! The sparse Cholesky factor of K_ii, with faer's AMD ordering or squeal's geometric nested
//! dissection (`squeal_fe::nested_dissection`) when the interior DOFs' coordinates are known.

use super::partition::Sparse;
use crate::error::ReductionError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::{Conj, MatMut, Par, Side, Spec};
use serde::Serialize;
use squeal_fe::cholesky::SplitCholesky;
use squeal_fe::ordering::{nested_dissection, NestedDissectionOptions, AUTO_ND_MIN_DOFS};
use squeal_meshes::Real;
use std::time::Instant;

/// The fill-reducing ordering the factor of K_ii used.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum KiiOrdering {
    /// faer's approximate minimum degree (no coordinates, or fewer than 20 000 interior DOFs).
    #[default]
    Amd,
    /// Geometric nested dissection on the interior DOFs' coordinates.
    NestedDissection,
}

/// A Cholesky factor of K_ii.
pub(crate) enum KiiFactor {
    Amd(Llt<usize, Real>),
    Custom(Box<SymbolicCholesky<usize>>, Vec<Real>),
    /// The nested dissection's two halves factorised and solved in parallel.
    Split(Box<SplitCholesky>),
}

/// What factorising gave besides the factor.
pub(crate) struct FactorInfo {
    pub ordering: KiiOrdering,
    pub ordering_s: Real,
    pub factor_nnz: usize,
}

impl KiiFactor {
    /// Factorises `kii` (its lower triangle is read). With `coords` (one point per interior
    /// DOF) and at least [`AUTO_ND_MIN_DOFS`] DOFs the ordering is nested dissection, else AMD.
    pub(crate) fn new(
        kii: &Sparse,
        coords: Option<&[[Real; 3]]>,
    ) -> Result<(KiiFactor, FactorInfo), ReductionError> {
        let n = kii.ncols();
        let fail = |detail: String| ReductionError::Factorization {
            what:
                "interior stiffness K_ii (the boundary DOFs must restrain every rigid-body motion)"
                    .into(),
            n,
            detail,
        };
        match coords.filter(|c| n >= AUTO_ND_MIN_DOFS && c.len() == n) {
            None => {
                let sym = SymbolicLlt::try_new(kii.symbolic(), Side::Lower)
                    .map_err(|e| fail(format!("{e:?}")))?;
                let llt = Llt::try_new_with_symbolic(sym, kii.as_ref(), Side::Lower)
                    .map_err(|e| fail(format!("{e:?}")))?;
                Ok((
                    KiiFactor::Amd(llt),
                    FactorInfo {
                        ordering: KiiOrdering::Amd,
                        ordering_s: 0.0,
                        factor_nnz: 0,
                    },
                ))
            }
            Some(c) => {
                let t = Instant::now();
                let (perm, nd) =
                    nested_dissection(kii.symbolic(), c, &NestedDissectionOptions::default())
                        .map_err(|e| fail(format!("nested dissection: {e}")))?;
                let ordering_s = t.elapsed().as_secs_f64();
                let [n1, n2, _] = nd.top_split_dofs;
                if n1 > 0 && n2 > 0 {
                    if let Ok(f) = SplitCholesky::factorize(kii.as_ref(), &perm, nd.top_split_dofs)
                    {
                        let factor_nnz = f.stats().factor_nnz;
                        return Ok((
                            KiiFactor::Split(Box::new(f)),
                            FactorInfo {
                                ordering: KiiOrdering::NestedDissection,
                                ordering_s,
                                factor_nnz,
                            },
                        ));
                    }
                }
                let ordering =
                    SymmetricOrdering::Custom(PermRef::new_checked(&perm.perm, &perm.perm_inv, n));
                let sym = factorize_symbolic_cholesky(
                    kii.symbolic(),
                    Side::Lower,
                    ordering,
                    Default::default(),
                )
                .map_err(|e| fail(format!("symbolic: {e:?}")))?;
                let mut vals = vec![0.0; sym.len_val()];
                let par = Par::rayon(0);
                let mut buf = MemBuffer::try_new(
                    sym.factorize_numeric_llt_scratch::<Real>(par, Spec::default()),
                )
                .map_err(|e| fail(format!("workspace: {e:?}")))?;
                sym.factorize_numeric_llt(
                    &mut vals,
                    kii.as_ref(),
                    Side::Lower,
                    LltRegularization::default(),
                    par,
                    MemStack::new(&mut buf),
                    Spec::default(),
                )
                .map_err(|e| fail(format!("{e:?}")))?;
                let factor_nnz = vals.len();
                Ok((
                    KiiFactor::Custom(Box::new(sym), vals),
                    FactorInfo {
                        ordering: KiiOrdering::NestedDissection,
                        ordering_s,
                        factor_nnz,
                    },
                ))
            }
        }
    }

    /// Whether one solve already uses every thread (the split factor's two halves run in
    /// parallel): callers then pass whole blocks instead of splitting the columns.
    pub(crate) fn is_parallel(&self) -> bool {
        matches!(self, KiiFactor::Split(_))
    }

    /// Overwrites `rhs` with K_ii⁻¹ rhs (one pass over the factor; sequential unless
    /// [`KiiFactor::is_parallel`]: callers split the columns over the threads).
    pub(crate) fn solve_in_place(&self, rhs: MatMut<'_, Real>) {
        match self {
            KiiFactor::Split(f) => f.solve_in_place(rhs),
            KiiFactor::Amd(llt) => llt.solve_in_place(rhs),
            KiiFactor::Custom(sym, vals) => {
                let par = Par::Seq;
                let mut buf = MemBuffer::new(sym.solve_in_place_scratch::<Real>(rhs.ncols(), par));
                LltRef::new(sym, vals).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    par,
                    MemStack::new(&mut buf),
                );
            }
        }
    }
}
