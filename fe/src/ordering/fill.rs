//! Fill of the Cholesky factor under an ordering, from the symbolic factorisation alone.

use super::DofPermutation;
use crate::FeError;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::SymbolicSparseColMatRef;
use faer::Side;
use serde::Serialize;

/// Size and cost of a Cholesky factor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CholeskyFill {
    /// Stored entries of L (supernodal: including the explicit zeros of the dense blocks).
    pub factor_nnz: usize,
    /// Σ_j n_j², n_j = entries below the diagonal of column j: the multiply–add count of the
    /// numeric factorisation (0 when the factor is simplicial).
    pub factor_flops: f64,
    /// Whether faer chose the supernodal factorisation.
    pub supernodal: bool,
}

impl CholeskyFill {
    /// Fill of an existing symbolic factorisation.
    pub fn of(sym: &SymbolicCholesky<usize>) -> Self {
        let (supernodal, factor_flops) = match sym.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let (begin, end, ptr) = (
                    s.supernode_begin(),
                    s.supernode_end(),
                    s.col_ptr_for_row_idx(),
                );
                let mut f = 0.0;
                for k in 0..s.n_supernodes() {
                    let c = end[k] - begin[k];
                    let p = ptr[k + 1] - ptr[k];
                    for j in 0..c {
                        let nj = (c - 1 - j + p) as f64;
                        f += nj * nj;
                    }
                }
                (true, f)
            }
            SymbolicCholeskyRaw::Simplicial(_) => (false, 0.0),
        };
        CholeskyFill {
            factor_nnz: sym.len_val(),
            factor_flops,
            supernodal,
        }
    }
}

/// Fill of the Cholesky factor of a symmetric matrix with the pattern `pattern` (lower triangle
/// or both) under `perm`, or under faer's AMD when `perm` is `None`. Symbolic only.
pub fn cholesky_fill(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    perm: Option<&DofPermutation>,
) -> Result<CholeskyFill, FeError> {
    let n = pattern.ncols();
    if let Some(p) = perm {
        if p.perm.len() != n {
            return Err(FeError::Dimension {
                what: "permutation length",
                got: p.perm.len(),
                expected: n,
            });
        }
    }
    let ord = match perm {
        Some(p) => SymmetricOrdering::Custom(PermRef::new_checked(&p.perm, &p.perm_inv, n)),
        None => SymmetricOrdering::Amd,
    };
    let sym = factorize_symbolic_cholesky(pattern, Side::Lower, ord, Default::default()).map_err(
        |e| FeError::Factorisation {
            what: "symbolic Cholesky".to_string(),
            reason: format!("{e:?}"),
        },
    )?;
    Ok(CholeskyFill::of(&sym))
}
