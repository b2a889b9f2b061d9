//! First level: one substructure's Craig–Bampton reduction onto its neighbouring groups.
//!
//! # Derivation
//! With its neighbours moving as u_c = L c (separator pieces, boundary), the substructure's DOFs
//! are u_j = Ψ_j c + Φ_j q_j with Ψ_j = −K_jj⁻¹ K_jc L (K_jc L = `Kc` below) and Φ_j the
//! K_jj-modes below the substructure's cut-off (M_jj-orthonormal). Its part of the second-level
//! matrices over [q_j, c] is
//!
//! K: [[diag μ_j, 0], [0, Kcᵀ Ψ_j]]  (K_jj Ψ_j + Kc = 0 decouples q_j),
//! M: [[I, Φ_jᵀ W], [Wᵀ Φ_j, Ψ_jᵀ W + Mcᵀ Ψ_j]] with W = M_jj Ψ_j + Mc,
//!
//! the groups' own Lᵀ A L blocks being added once at assembly.

use super::super::eigen::{self, LanczosParams, Want};
use super::super::partition::{at_b, sym_spmm, to_dense};
use super::groups::{adjacent, coupling, submatrix, Group, Slot};
use crate::cb::Sparse;
use crate::error::ReductionError;
use faer::Mat;
use squeal_fe::cholesky::BorderedCholesky;
use squeal_meshes::Real;

/// One substructure's contribution to the second level.
pub(super) struct Level1 {
    /// Adjacent groups (coordinates `c` = theirs, in this order).
    pub adj: Vec<usize>,
    /// Eigenvalues and M_jj-orthonormal shapes of the kept fixed-interface modes (own order).
    pub mu: Vec<Real>,
    pub phi: Mat<Real>,
    /// Kcᵀ Ψ_j, Ψ_jᵀW + Mcᵀ Ψ_j (c × c) and Φ_jᵀ W (k × c).
    pub kcc: Mat<Real>,
    pub mcc: Mat<Real>,
    pub mqc: Mat<Real>,
    /// λ of the cut-off used.
    pub cutoff: Real,
}

/// Reduces substructure `own` (component DOFs, factor order) with its modes up to eigenvalue
/// `cutoff`.
pub(super) fn reduce(
    k: &Sparse,
    m: &Sparse,
    own: &[usize],
    slot: &[Slot],
    groups: &[Group],
    cutoff: Real,
    lanczos: LanczosParams,
    dense_max: usize,
    interrupt: &squeal_fe::Interrupt,
) -> Result<Level1, ReductionError> {
    let n = k.nrows();
    let nj = own.len();
    let what = format!("substructure of {nj} DOFs");
    let factor = BorderedCholesky::factorize(k.as_ref(), own, &[]).map_err(|e| {
        ReductionError::Factorization {
            what: what.clone(),
            n: nj,
            detail: e.to_string(),
        }
    })?;
    let adj = adjacent(k, own, slot);
    let kc = coupling(k, own, slot, groups, &adj);
    let mc = coupling(m, own, slot, groups, &adj);
    let mut psi = -&kc;
    factor.solve_own(psi.as_mut());
    let m_jj = submatrix(m, own, n);
    let want = Want {
        lambda_max: Some(cutoff),
        n_max: None,
    };
    let pairs = if nj <= dense_max {
        let k_jj = submatrix(k, own, n);
        eigen::dense(
            to_dense(&k_jj).as_ref(),
            to_dense(&m_jj).as_ref(),
            want,
            &what,
        )?
    } else {
        // The number of modes below the cut-off is not known in advance: a Krylov space too
        // small for them is doubled (up to half the substructure).
        let solve = |x: faer::MatMut<'_, Real>| factor.solve_own(x);
        let mut params = lanczos;
        loop {
            match eigen::lanczos(&solve, &m_jj, 0.0, want, params, &what, interrupt) {
                Ok(p) => break p,
                Err(ReductionError::Eigen { .. }) if 2 * params.max_dim <= nj / 2 => {
                    params.max_dim *= 2;
                }
                Err(e) => return Err(e),
            }
        }
    };
    let mut w = sym_spmm(&m_jj, psi.as_ref());
    w += &mc;
    let kcc = sym(at_b(kc.as_ref(), psi.as_ref()));
    let mcc = sym(at_b(psi.as_ref(), w.as_ref()) + at_b(mc.as_ref(), psi.as_ref()));
    let mqc = at_b(pairs.vectors.as_ref(), w.as_ref());
    Ok(Level1 {
        adj,
        mu: pairs.values,
        phi: pairs.vectors,
        kcc,
        mcc,
        mqc,
        cutoff,
    })
}

pub(super) fn sym(a: Mat<Real>) -> Mat<Real> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}
