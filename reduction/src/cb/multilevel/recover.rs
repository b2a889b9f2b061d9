//! Second pass: each substructure factorised again with its separator pieces as border, its
//! DOFs recovered for every reduced coordinate, and the error estimates.
//!
//! # Error estimates
//! Let u be a recovered column (a constraint mode, θ = 0, or a fixed-interface mode with
//! eigenvalue θ) and r = (K − θM)u on the component's interior. The reduction is a Rayleigh–Ritz
//! projection, so r is orthogonal to every retained shape, and the first-order correction the
//! discarded shapes would bring changes the energy (or the eigenvalue) by about
//! rᵀ(K − θM)⁻¹r. That is split by where the discarded shapes live:
//!
//! - substructure j (its modes above the cut-off μ_c, the separators held): r_jᵀ(K_jj − θM_jj)⁻¹r_j
//!   ≤ μ_c/(μ_c − θ) · r_jᵀ K_jj⁻¹ r_j, with the substructure's own factor;
//! - separator piece s (shapes beyond its polynomials, the adjacent substructures following
//!   statically, every other separator held): r_sᵀ S_s⁻¹ r_s with S_s = K_ss − Σ_j K_sj K_jj⁻¹ K_js
//!   assembled from the adjacent substructures' bordered factors (T_j T_jᵀ blocks).
//!
//! Relative to θ for modes and to the condensed stiffness K_r[c, c] for constraint modes. Their
//! sum over substructures and pieces estimates the relative error of each reduced quantity
//! (the block-diagonal part of (K − θM)⁻¹; exact when the discarded shapes do not interact).
//!
//! # Reference
//! Bennighof & Lehoucq, SIAM J. Sci. Comput. 25 (2004) 2084–2106, §4 (truncation in
//! substructure eigenspaces); the residual form as in Yang, Gao, Bai, Li et al., "An algebraic
//! substructuring method for large-scale eigenvalue calculation", SIAM J. Sci. Comput. 27 (2005).

use super::super::partition::sym_spmm;
use super::groups::{coupling, submatrix, Group, Kind, Slot};
use super::level1::Level1;
use super::level2::Level2;
use crate::cb::Sparse;
use crate::error::ReductionError;
use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};
use squeal_fe::cholesky::BorderedCholesky;
use squeal_meshes::Real;

/// What the second pass gives for one substructure.
pub(super) struct Recovered {
    /// Its DOFs' values for every reduced coordinate [x_b, η] (own order).
    pub u: Mat<Real>,
    /// Its estimate per reduced coordinate (relative).
    pub estimate: Vec<Real>,
    /// T_s T_sᵀ for each adjacent separator piece (piece index, block).
    pub schur: Vec<(usize, Mat<Real>)>,
    /// −K_sj K_jj⁻¹ r_j for each adjacent piece: its part of the piece's condensed residual.
    pub condensed: Vec<(usize, Mat<Real>)>,
    pub factor_nnz: usize,
}

/// The full coordinates' rows for the groups' coordinates `adj` (c × n_r).
fn coupling_rows(adj: &[usize], groups: &[Group], l2: &Level2, nb: usize, ng: usize) -> Mat<Real> {
    let nr = l2.z.ncols();
    let c: usize = adj.iter().map(|&g| groups[g].n_coords()).sum();
    let mut rows = Mat::<Real>::zeros(c, nr);
    let mut r = 0;
    for &g in adj {
        for k in 0..groups[g].n_coords() {
            let gc = groups[g].coord0 + k;
            if gc < ng - nb {
                rows.row_mut(r).copy_from(l2.z.row(l2.g0 + gc));
            } else {
                rows[(r, gc - (ng - nb))] = 1.0;
            }
            r += 1;
        }
    }
    rows
}

/// θ of each reduced coordinate: 0 for the boundary ones, λ for the modes.
pub(super) fn thetas(l2: &Level2, nb: usize) -> Vec<Real> {
    (0..nb)
        .map(|_| 0.0)
        .chain(l2.lambda.iter().copied())
        .collect()
}

/// Recovers substructure `own` and estimates its truncation error.
#[allow(clippy::too_many_arguments)]
pub(super) fn substructure(
    k: &Sparse,
    m: &Sparse,
    own: &[usize],
    sub: &Level1,
    sub_q0: usize,
    slot: &[Slot],
    groups: &[Group],
    l2: &Level2,
    nb: usize,
    ng: usize,
) -> Result<Recovered, ReductionError> {
    let n = k.nrows();
    let nj = own.len();
    let pieces: Vec<usize> = sub
        .adj
        .iter()
        .copied()
        .filter(|&g| matches!(groups[g].kind, Kind::Separator(_)))
        .collect();
    let border: Vec<usize> = pieces
        .iter()
        .flat_map(|&g| groups[g].dofs.iter().copied())
        .collect();
    let factor = BorderedCholesky::factorize(k.as_ref(), own, &border).map_err(|e| {
        ReductionError::Factorization {
            what: format!("substructure of {nj} DOFs with its separators"),
            n: nj + border.len(),
            detail: e.to_string(),
        }
    })?;
    let zc = coupling_rows(&sub.adj, groups, l2, nb, ng);
    let kc = coupling(k, own, slot, groups, &sub.adj);
    let mc = coupling(m, own, slot, groups, &sub.adj);
    let kz = &kc * &zc;
    let mz = &mc * &zc;
    drop((kc, mc));
    let mut u = -&kz;
    factor.solve_own(u.as_mut());
    let kq = sub.mu.len();
    if kq > 0 {
        u += &sub.phi * l2.z.subrows(sub_q0, kq);
    }
    // Residual r = K_jj u + Kc zc − θ (M_jj u + Mc zc).
    let theta = thetas(l2, nb);
    let k_jj = submatrix(k, own, n);
    let m_jj = submatrix(m, own, n);
    let mut r = sym_spmm(&k_jj, u.as_ref()) + &kz;
    let mu_ = sym_spmm(&m_jj, u.as_ref()) + &mz;
    for (c, &th) in theta.iter().enumerate() {
        if th != 0.0 {
            for i in 0..nj {
                r[(i, c)] -= th * mu_[(i, c)];
            }
        }
    }
    drop((kz, mz, mu_));
    let mut x = r.clone();
    factor.solve_own(x.as_mut());
    let estimate: Vec<Real> = (0..theta.len())
        .map(|c| {
            let e: Real = (0..nj).map(|i| r[(i, c)] * x[(i, c)]).sum();
            let th = theta[c];
            if th > 0.0 {
                let amp = if sub.cutoff > th {
                    sub.cutoff / (sub.cutoff - th)
                } else {
                    Real::INFINITY
                };
                amp * e.abs() / th
            } else {
                let kcc = l2.k[(c, c)];
                e.abs() / kcc.abs().max(Real::MIN_POSITIVE)
            }
        })
        .collect();
    // T_s T_sᵀ and −K_sj K_jj⁻¹ r_j per adjacent piece.
    let t = factor.trailing();
    let mut schur = Vec::with_capacity(pieces.len());
    let mut condensed: Vec<(usize, Mat<Real>)> = Vec::with_capacity(pieces.len());
    let mut r0 = 0;
    for &g in &pieces {
        let len = groups[g].dofs.len();
        let ts = t.subrows(r0, len);
        let Kind::Separator(p) = groups[g].kind else {
            unreachable!()
        };
        schur.push((p, ts * ts.transpose()));
        condensed.push((p, Mat::zeros(len, theta.len())));
        r0 += len;
    }
    for (l, &d) in own.iter().enumerate() {
        for (&i, &v) in k.row_idx_of_col_raw(d).iter().zip(k.val_of_col(d)) {
            if let Slot::Grp(g, pos) = slot[i] {
                if let Some(q) = pieces.iter().position(|&pg| pg == g as usize) {
                    let c = &mut condensed[q].1;
                    for col in 0..theta.len() {
                        c[(pos as usize, col)] -= v * x[(l, col)];
                    }
                }
            }
        }
    }
    Ok(Recovered {
        u,
        estimate,
        schur,
        condensed,
        factor_nnz: factor.fill().factor_nnz,
    })
}

/// The error estimate of separator piece `g` (its DOFs are interior; `value(d)` gives the row
/// of the recovered columns at any component DOF), from S = Σ T Tᵀ − (count − 1) K_ss.
#[allow(clippy::too_many_arguments)]
pub(super) fn separator(
    k: &Sparse,
    m: &Sparse,
    group: &Group,
    schur_sum: Mat<Real>,
    count: usize,
    condensed: Mat<Real>,
    value: &dyn Fn(usize) -> Vec<Real>,
    theta: &[Real],
    kr: MatRef<'_, Real>,
) -> Result<Vec<Real>, ReductionError> {
    let dofs = &group.dofs;
    let ns = dofs.len();
    let n = k.nrows();
    let k_ss = submatrix(k, dofs, n);
    let mut s = schur_sum;
    let extra = count.saturating_sub(1) as Real;
    if extra > 0.0 {
        let (cp, ri, v) = (
            k_ss.symbolic().col_ptr(),
            k_ss.symbolic().row_idx(),
            k_ss.val(),
        );
        for j in 0..ns {
            for p in cp[j]..cp[j + 1] {
                s[(ri[p], j)] -= extra * v[p];
            }
        }
    }
    let nr = theta.len();
    // The recovered rows of every DOF the piece's rows of K and M touch.
    let mut touched: Vec<usize> = dofs
        .iter()
        .flat_map(|&d| {
            k.row_idx_of_col_raw(d)
                .iter()
                .chain(m.row_idx_of_col_raw(d))
                .copied()
        })
        .collect();
    touched.sort_unstable();
    touched.dedup();
    let rows: Vec<Vec<Real>> = touched.iter().map(|&d| value(d)).collect();
    let at = |d: usize| &rows[touched.binary_search(&d).expect("touched")];
    // r̂_s = r_s − Σ_j K_sj K_jj⁻¹ r_j: the residual condensed onto the piece, the adjacent
    // substructures following statically.
    let mut r = condensed;
    for (row, &d) in dofs.iter().enumerate() {
        for (&i, &v) in k.row_idx_of_col_raw(d).iter().zip(k.val_of_col(d)) {
            let u = at(i);
            for c in 0..nr {
                r[(row, c)] += v * u[c];
            }
        }
        for (&i, &v) in m.row_idx_of_col_raw(d).iter().zip(m.val_of_col(d)) {
            let u = at(i);
            for c in 0..nr {
                r[(row, c)] -= theta[c] * v * u[c];
            }
        }
    }
    let llt = s
        .llt(Side::Lower)
        .map_err(|e| ReductionError::Factorization {
            what: "a separator piece's condensed stiffness (error estimate)".into(),
            n: ns,
            detail: format!("{e:?}"),
        })?;
    let x = llt.solve(&r);
    Ok((0..nr)
        .map(|c| {
            let e: Real = (0..ns).map(|i| r[(i, c)] * x[(i, c)]).sum::<Real>().abs();
            let th = theta[c];
            if th > 0.0 {
                e / th
            } else {
                e / kr[(c, c)].abs().max(Real::MIN_POSITIVE)
            }
        })
        .collect())
}
