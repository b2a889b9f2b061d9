//! Second level: the substructures' modal coordinates, the separator coordinates and the
//! component's boundary coordinates assembled into one dense model, and its Craig–Bampton
//! reduction onto the boundary coordinates.
//!
//! Coordinates: [q₁ … q_P, separator coordinates, kept boundary DOFs, interface coordinates];
//! the interior of this level is everything before the kept DOFs. Since every substructure's q
//! is stiffness-decoupled, K₂ is diagonal on the modal coordinates.

use super::super::eigen::{self, Want};
use super::groups::Group;
use super::level1::{sym, Level1};
use crate::error::ReductionError;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use squeal_meshes::Real;

/// The second level reduced: the component's reduced K, M, fixed-interface eigenvalues, and the
/// second-level interior coordinates as functions of [x_b, η] (`z`: n₂ᵢ × (n_b + n_q)).
pub(super) struct Level2 {
    pub k: Mat<Real>,
    pub m: Mat<Real>,
    pub lambda: Vec<Real>,
    pub z: Mat<Real>,
    /// Start of each substructure's modal block, and of the groups' coordinates, in the
    /// second-level numbering.
    pub q0: Vec<usize>,
    pub g0: usize,
    pub sizes: [usize; 3],
}

/// Assembles and reduces. `kg`, `mg` = the groups' Lᵀ A L (their numbering); the last `nb` of
/// the groups' coordinates are the boundary (kept, interface).
pub(super) fn reduce(
    subs: &[&Level1],
    groups: &[Group],
    kg: &Mat<Real>,
    mg: &Mat<Real>,
    nb: usize,
    want: Want,
) -> Result<Level2, ReductionError> {
    let mut q0 = Vec::with_capacity(subs.len());
    let mut nq = 0;
    for s in subs {
        q0.push(nq);
        nq += s.mu.len();
    }
    let ng = kg.nrows();
    let n2 = nq + ng;
    let mut k2 = Mat::<Real>::zeros(n2, n2);
    let mut m2 = Mat::<Real>::zeros(n2, n2);
    k2.submatrix_mut(nq, nq, ng, ng).copy_from(kg);
    m2.submatrix_mut(nq, nq, ng, ng).copy_from(mg);
    for (s, &o) in subs.iter().zip(&q0) {
        // Level-2 index of each of the substructure's coupling coordinates.
        let idx: Vec<usize> = s
            .adj
            .iter()
            .flat_map(|&g| {
                let c0 = nq + groups[g].coord0;
                c0..c0 + groups[g].n_coords()
            })
            .collect();
        for (a, &ia) in idx.iter().enumerate() {
            for (b, &ib) in idx.iter().enumerate() {
                k2[(ia, ib)] += s.kcc[(a, b)];
                m2[(ia, ib)] += s.mcc[(a, b)];
            }
        }
        for (r, &mu) in s.mu.iter().enumerate() {
            k2[(o + r, o + r)] = mu;
            m2[(o + r, o + r)] = 1.0;
            for (b, &ib) in idx.iter().enumerate() {
                m2[(o + r, ib)] = s.mqc[(r, b)];
                m2[(ib, o + r)] = s.mqc[(r, b)];
            }
        }
    }
    let ni = n2 - nb;
    let kii = k2.submatrix(0, 0, ni, ni).to_owned();
    let kib = k2.submatrix(0, ni, ni, nb).to_owned();
    let llt = kii
        .llt(Side::Lower)
        .map_err(|e| ReductionError::Factorization {
            what: "second-level interior stiffness (substructure modes and separators)".into(),
            n: ni,
            detail: format!("{e:?}"),
        })?;
    let psi = -llt.solve(&kib);
    let pairs = eigen::dense(
        kii.as_ref(),
        m2.submatrix(0, 0, ni, ni),
        want,
        "second-level fixed-interface modes",
    )?;
    drop(kii);
    let nmodes = pairs.values.len();
    let mii = m2.submatrix(0, 0, ni, ni);
    let mib = m2.submatrix(0, ni, ni, nb);
    let w = mii * &psi + mib;
    let kbb = sym(k2.submatrix(ni, ni, nb, nb).to_owned() + kib.transpose() * &psi);
    let mbb = sym(m2.submatrix(ni, ni, nb, nb).to_owned()
        + mib.transpose() * &psi
        + psi.transpose() * &w);
    let mbq = w.transpose() * &pairs.vectors;
    let nr = nb + nmodes;
    let mut k = Mat::<Real>::zeros(nr, nr);
    let mut m = Mat::<Real>::zeros(nr, nr);
    k.submatrix_mut(0, 0, nb, nb).copy_from(&kbb);
    m.submatrix_mut(0, 0, nb, nb).copy_from(&mbb);
    m.submatrix_mut(0, nb, nb, nmodes).copy_from(&mbq);
    m.submatrix_mut(nb, 0, nmodes, nb)
        .copy_from(mbq.transpose());
    for (j, &l) in pairs.values.iter().enumerate() {
        k[(nb + j, nb + j)] = l;
        m[(nb + j, nb + j)] = 1.0;
    }
    let mut z = Mat::<Real>::zeros(ni, nr);
    z.submatrix_mut(0, 0, ni, nb).copy_from(&psi);
    z.submatrix_mut(0, nb, ni, nmodes).copy_from(&pairs.vectors);
    Ok(Level2 {
        k,
        m,
        lambda: pairs.values,
        z,
        q0,
        g0: nq,
        sizes: [nq, ng - nb, nb],
    })
}
