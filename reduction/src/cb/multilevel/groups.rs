//! Coordinate groups of the second level: separator pieces (polynomial bases), the kept boundary
//! DOFs (identity) and the interface DOFs (their basis); and the products of K or M with them.

use super::super::interface::{polynomial_basis_2d, InterfaceDof};
use super::super::partition::Sparse;
use crate::error::ReductionError;
use faer::Mat;
use squeal_meshes::Real;
use std::collections::BTreeMap;

/// What a group is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// Separator piece (its index among the pieces).
    Separator(usize),
    /// Kept boundary DOFs (identity basis).
    Kept,
    /// Interface DOFs (the component's interface basis).
    Interface,
}

/// DOFs moving as `dofs = basis · coords`.
pub(super) struct Group {
    pub kind: Kind,
    pub dofs: Vec<usize>,
    pub basis: Mat<Real>,
    /// First coordinate in the groups' numbering (separators, then kept, then interface).
    pub coord0: usize,
}

impl Group {
    pub fn n_coords(&self) -> usize {
        self.basis.ncols()
    }
}

/// Where each component DOF is: `Own(j, local)` in substructure j, `Grp(g, pos)` in group g.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Slot {
    Own(u32, u32),
    Grp(u32, u32),
    Free,
}

/// A separator piece's basis: 2-D polynomials of total degree ≤ `degree` in the piece's plane,
/// per DOF slot of its nodes (the DOFs of one node are consecutive at one point).
pub(super) fn separator_basis(
    dofs: &[usize],
    coords: &[[Real; 3]],
    degree: usize,
) -> Result<Mat<Real>, ReductionError> {
    let mut list = Vec::with_capacity(dofs.len());
    let mut slot = 0;
    for (i, &d) in dofs.iter().enumerate() {
        slot = if i > 0 && coords[d] == coords[dofs[i - 1]] {
            slot + 1
        } else {
            0
        };
        list.push(InterfaceDof {
            point: coords[d],
            direction: slot.min(2),
            patch: 0,
        });
    }
    polynomial_basis_2d(&list, degree)
}

/// Numbers the groups' coordinates in order; returns the total.
pub(super) fn number(groups: &mut [Group]) -> usize {
    let mut c = 0;
    for g in groups.iter_mut() {
        g.coord0 = c;
        c += g.n_coords();
    }
    c
}

/// Groups adjacent to the DOFs `own` through `a`'s pattern (increasing group index).
pub(super) fn adjacent(a: &Sparse, own: &[usize], slot: &[Slot]) -> Vec<usize> {
    let mut adj: Vec<usize> = own
        .iter()
        .flat_map(|&d| a.row_idx_of_col_raw(d).iter())
        .filter_map(|&i| match slot[i] {
            Slot::Grp(g, _) => Some(g as usize),
            _ => None,
        })
        .collect();
    adj.sort_unstable();
    adj.dedup();
    adj
}

/// A_{own, groups adj} · blockdiag(L_g): n_own × Σ n_g (columns group by group in `adj` order).
/// `local[d]` = row of DOF d in `own` (usize::MAX elsewhere).
pub(super) fn coupling(
    a: &Sparse,
    own: &[usize],
    slot: &[Slot],
    groups: &[Group],
    adj: &[usize],
) -> Mat<Real> {
    let mut col0 = BTreeMap::new();
    let mut c = 0;
    for &g in adj {
        col0.insert(g, c);
        c += groups[g].n_coords();
    }
    let mut out = Mat::<Real>::zeros(own.len(), c);
    // Row r of the result: Σ over the column `own[r]` of A (symmetric) of A[i, own[r]] L_g[pos(i)].
    for (r, &d) in own.iter().enumerate() {
        for (&i, &v) in a.row_idx_of_col_raw(d).iter().zip(a.val_of_col(d)) {
            if let Slot::Grp(g, p) = slot[i] {
                let Some(&c0) = col0.get(&(g as usize)) else {
                    continue;
                };
                let b = &groups[g as usize].basis;
                for k in 0..b.ncols() {
                    out[(r, c0 + k)] += v * b[(p as usize, k)];
                }
            }
        }
    }
    out
}

/// Lᵀ A L over all groups (N_g × N_g dense, the groups' numbering).
pub(super) fn self_terms(
    a: &Sparse,
    slot: &[Slot],
    groups: &[Group],
    n_coords: usize,
) -> Mat<Real> {
    let mut out = Mat::<Real>::zeros(n_coords, n_coords);
    for grp in groups {
        // Y_h = A_{h, g} L_g for each group h touched.
        let mut y: BTreeMap<usize, Mat<Real>> = BTreeMap::new();
        for (r, &d) in grp.dofs.iter().enumerate() {
            for (&i, &v) in a.row_idx_of_col_raw(d).iter().zip(a.val_of_col(d)) {
                if let Slot::Grp(h, t) = slot[i] {
                    let h = h as usize;
                    let yh = y
                        .entry(h)
                        .or_insert_with(|| Mat::zeros(groups[h].dofs.len(), grp.n_coords()));
                    for k in 0..grp.n_coords() {
                        yh[(t as usize, k)] += v * grp.basis[(r, k)];
                    }
                }
            }
        }
        for (h, yh) in y {
            let blk = groups[h].basis.transpose() * &yh;
            out.submatrix_mut(groups[h].coord0, grp.coord0, blk.nrows(), blk.ncols())
                .copy_from(&blk);
        }
    }
    // Exact symmetry (the blocks were formed once each way).
    Mat::from_fn(n_coords, n_coords, |i, j| 0.5 * (out[(i, j)] + out[(j, i)]))
}

/// A restricted to `rows` (full storage, in that order).
pub(super) fn submatrix(a: &Sparse, rows: &[usize], n_all: usize) -> Sparse {
    let mut local = vec![usize::MAX; n_all];
    for (l, &i) in rows.iter().enumerate() {
        local[i] = l;
    }
    let cols: Vec<Vec<(usize, Real)>> = rows
        .iter()
        .map(|&d| {
            a.row_idx_of_col_raw(d)
                .iter()
                .zip(a.val_of_col(d))
                .filter(|(&i, _)| local[i] != usize::MAX)
                .map(|(&i, &v)| (local[i], v))
                .collect()
        })
        .collect();
    super::super::partition::from_columns(rows.len(), cols)
}
