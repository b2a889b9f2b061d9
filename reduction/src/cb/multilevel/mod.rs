//! Substructured (two-level) Craig–Bampton reduction of a large component, with memory bounded by
//! its largest substructure's factor instead of the whole interior's.
//!
//! 1. The interior is cut by the recursive bisection of [`squeal_fe::ordering::substructure`]
//!    into substructures of at most `max_dofs` DOFs; the separators between them are split into
//!    connected pieces.
//! 2. Each separator piece moves in a polynomial basis of its plane (degree chosen per piece),
//!    as the contact patches do with an interface basis.
//! 3. First level, substructure by substructure (two at a time, each factor freed after use):
//!    Craig–Bampton onto its neighbouring pieces and boundary groups, keeping its
//!    fixed-interface modes up to `cutoff_factor` × the component's cut-off.
//! 4. Second level: the substructures' modal coordinates, the separator coordinates and the
//!    component's boundary coordinates form one dense model, reduced by Craig–Bampton onto the
//!    boundary coordinates with the component's cut-off: the component's reduced model.
//! 5. Second pass, substructure by substructure: its factor again with its separator pieces as
//!    border; the recovery of its DOFs for every reduced coordinate (the model's Ψ and Φ); the
//!    error estimate of its mode truncation and the condensed stiffness of its pieces, for their
//!    estimates ([`recover`]). A tolerance decides: while the summed estimate of a reduced
//!    quantity is above `tol`, the substructures and pieces with the largest estimates (until
//!    the others leave less than `tol`/2) get more modes (cut-off × 1.6) or a higher degree
//!    (+ 2), and the reduction is repeated (at most `max_rounds` times).
//!
//! The constraint modes are static responses through the polynomial separators, the
//! fixed-interface modes Ritz vectors of the substructures' modes and separator shapes: the model
//! is a Rayleigh–Ritz projection of the component, its frequencies above the exact
//! Craig–Bampton ones.
//!
//! # Reference
//! Bennighof & Lehoucq, "An automated multilevel substructuring method for eigenspace
//! computation in linear elastodynamics", SIAM J. Sci. Comput. 25 (2004) 2084–2106; Kaplan,
//! "Implementation of automated multilevel substructuring for frequency response analysis of
//! structures", PhD thesis, U. Texas at Austin (2001); Gao, Li, Yang, Bai, "An implementation
//! and evaluation of the AMLS method for sparse eigenvalue problems", ACM TOMS 34 (2008) 20;
//! the separator reduction is an interface reduction as reviewed by Krattiger et al.,
//! "Interface reduction for Hurty/Craig-Bampton substructured models: review and
//! improvements", Mech. Syst. Signal Process. 114 (2019) 579–603. `docs/multilevel.md`.

mod groups;
mod level1;
mod level2;
mod options;
mod recover;

pub use options::{MultilevelStats, SeparatorStats, SubstructureOptions, SubstructureStats};

use super::eigen::{LanczosParams, Want};
use super::interface::InterfaceBasis;
use super::model::{peak_rss_kib, CbModel, CbStats, EigenMethod, PhaseMemory};
use super::options::CbOptions;
use super::partition::Sparse;
use crate::error::ReductionError;
use faer::sparse::SymbolicSparseColMat;
use faer::Mat;
use groups::{Group, Kind, Slot};
use level1::Level1;
use rayon::prelude::*;
use squeal_meshes::Real;
use std::f64::consts::PI;
use std::time::Instant;

/// Substructured reduction of (k, m) onto `boundary` and the `interface` basis ([module
/// docs](self)); `coords` = the point of every DOF.
pub(crate) fn reduce(
    k: &Sparse,
    m: &Sparse,
    boundary: &[usize],
    interface: Option<&InterfaceBasis>,
    opts: &CbOptions,
    coords: &[[Real; 3]],
) -> Result<CbModel, ReductionError> {
    let sub = &opts.substructures;
    let t_start = Instant::now();
    let n = k.nrows();
    let lambda_c = match opts.resolved_cutoff_hz() {
        Some(f) => (2.0 * PI * f).powi(2),
        None => {
            return Err(ReductionError::InvalidOption {
                field: "cutoff_hz",
                value: "none".into(),
                reason: "substructures need a cut-off frequency (cutoff_hz or \
                         frequency_of_interest_hz)"
                    .into(),
            })
        }
    };
    // Interior and its substructures.
    let mut is_b = vec![false; n];
    for &d in boundary
        .iter()
        .chain(interface.iter().flat_map(|f| f.dofs.iter()))
    {
        is_b[d] = true;
    }
    let interior: Vec<usize> = (0..n).filter(|&d| !is_b[d]).collect();
    let mut int_of = vec![usize::MAX; n];
    for (i, &d) in interior.iter().enumerate() {
        int_of[d] = i;
    }
    let pattern = sub_pattern(k, &interior, &int_of);
    let int_coords: Vec<[Real; 3]> = interior.iter().map(|&d| coords[d]).collect();
    let s = squeal_fe::ordering::substructure(
        pattern.as_ref(),
        &int_coords,
        sub.max_dofs,
        &Default::default(),
    )
    .map_err(|e| ReductionError::InvalidOption {
        field: "substructures",
        value: format!("max_dofs = {}", sub.max_dofs),
        reason: e.to_string(),
    })?;
    drop((pattern, int_coords));
    let subs_dofs: Vec<Vec<usize>> = s
        .substructures
        .iter()
        .map(|v| v.iter().map(|&i| interior[i]).collect())
        .collect();
    let pieces: Vec<Vec<usize>> = s
        .separators
        .iter()
        .map(|v| v.iter().map(|&i| interior[i]).collect())
        .collect();
    let substructuring_s = t_start.elapsed().as_secs_f64();

    // Groups: separator pieces, kept boundary, interface; and where each DOF is.
    let mut degrees = vec![sub.degree; pieces.len()];
    let mut groups: Vec<Group> = Vec::new();
    for (p, dofs) in pieces.iter().enumerate() {
        groups.push(Group {
            kind: Kind::Separator(p),
            dofs: dofs.clone(),
            basis: groups::separator_basis(dofs, coords, degrees[p])?,
            coord0: 0,
        });
    }
    if !boundary.is_empty() {
        groups.push(Group {
            kind: Kind::Kept,
            dofs: boundary.to_vec(),
            basis: Mat::identity(boundary.len(), boundary.len()),
            coord0: 0,
        });
    }
    if let Some(f) = interface {
        groups.push(Group {
            kind: Kind::Interface,
            dofs: f.dofs.clone(),
            basis: f.basis.clone(),
            coord0: 0,
        });
    }
    let mut slot = vec![Slot::Free; n];
    for (j, dofs) in subs_dofs.iter().enumerate() {
        for (l, &d) in dofs.iter().enumerate() {
            slot[d] = Slot::Own(j as u32, l as u32);
        }
    }
    for (g, grp) in groups.iter().enumerate() {
        for (p, &d) in grp.dofs.iter().enumerate() {
            slot[d] = Slot::Grp(g as u32, p as u32);
        }
    }
    let nb = boundary.len() + interface.map_or(0, |f| f.n_coords());

    let lanczos = LanczosParams {
        block: opts.lanczos_block,
        max_dim: opts.lanczos_max_dim,
        tol: opts.lanczos_tol,
    };
    let mut cutoffs = vec![lambda_c * sub.cutoff_factor.powi(2); subs_dofs.len()];
    let mut level1: Vec<Option<Level1>> = (0..subs_dofs.len()).map(|_| None).collect();
    let mut mem = PhaseMemory::default();
    let (mut level1_s, mut level2_s, mut recovery_s) = (0.0, 0.0, 0.0);
    let mut rounds = 0;
    let threads = rayon::current_num_threads().max(1);
    loop {
        opts.check_interrupt("the substructured reduction")?;
        rounds += 1;
        // First level for the substructures that need it, `threads` at a time.
        let t = Instant::now();
        let dirty: Vec<usize> = (0..subs_dofs.len())
            .filter(|&j| level1[j].is_none())
            .collect();
        for chunk in dirty.chunks(threads) {
            let done: Vec<Result<Level1, ReductionError>> = chunk
                .par_iter()
                .map(|&j| {
                    level1::reduce(
                        k,
                        m,
                        &subs_dofs[j],
                        &slot,
                        &groups,
                        cutoffs[j],
                        lanczos,
                        opts.dense_max,
                        &opts.interrupt,
                    )
                })
                .collect();
            for (&j, r) in chunk.iter().zip(done) {
                level1[j] = Some(r?);
            }
        }
        mem.factor = peak_rss_kib();
        level1_s += t.elapsed().as_secs_f64();

        // Second level.
        let t = Instant::now();
        let ng = groups::number(&mut groups);
        let kg = groups::self_terms(k, &slot, &groups, ng);
        let mg = groups::self_terms(m, &slot, &groups, ng);
        let subs: Vec<&Level1> = level1
            .iter()
            .map(|l| l.as_ref().expect("reduced"))
            .collect();
        let want = Want {
            lambda_max: Some(lambda_c),
            n_max: opts.n_modes,
        };
        let l2 = level2::reduce(&subs, &groups, &kg, &mg, nb, want)?;
        drop((kg, mg));
        level2_s += t.elapsed().as_secs_f64();

        // Recovery and estimates.
        let t = Instant::now();
        let nq = l2.lambda.len();
        let nr = nb + nq;
        let mut psi = Mat::<Real>::zeros(interior.len(), nb);
        let mut phi = Mat::<Real>::zeros(interior.len(), nq);
        let mut put = |d: usize, row: faer::RowRef<'_, Real>| {
            let i = int_of[d];
            for c in 0..nb {
                psi[(i, c)] = row[c];
            }
            for c in 0..nq {
                phi[(i, c)] = row[nb + c];
            }
        };
        // Separator DOFs: L_s times their coordinates' rows.
        for grp in groups
            .iter()
            .filter(|g| matches!(g.kind, Kind::Separator(_)))
        {
            let rows = l2.z.subrows(l2.g0 + grp.coord0, grp.n_coords());
            let u = &grp.basis * rows;
            for (r, &d) in grp.dofs.iter().enumerate() {
                put(d, u.row(r));
            }
        }
        let mut sub_est: Vec<Vec<Real>> = vec![Vec::new(); subs_dofs.len()];
        let mut sub_nnz = vec![0usize; subs_dofs.len()];
        let mut schur: Vec<Option<Mat<Real>>> = (0..pieces.len()).map(|_| None).collect();
        let mut condensed: Vec<Option<Mat<Real>>> = (0..pieces.len()).map(|_| None).collect();
        let mut schur_count = vec![0usize; pieces.len()];
        let order: Vec<usize> = (0..subs_dofs.len()).collect();
        for chunk in order.chunks(threads) {
            let done: Vec<Result<recover::Recovered, ReductionError>> = chunk
                .par_iter()
                .map(|&j| {
                    recover::substructure(
                        k,
                        m,
                        &subs_dofs[j],
                        subs[j],
                        l2.q0[j],
                        &slot,
                        &groups,
                        &l2,
                        nb,
                        ng,
                    )
                })
                .collect();
            for (&j, r) in chunk.iter().zip(done) {
                let r = r?;
                for (l, &d) in subs_dofs[j].iter().enumerate() {
                    put(d, r.u.row(l));
                }
                sub_est[j] = r.estimate;
                sub_nnz[j] = r.factor_nnz;
                for (p, blk) in r.schur {
                    schur_count[p] += 1;
                    match &mut schur[p] {
                        Some(s) => *s += &blk,
                        None => schur[p] = Some(blk),
                    }
                }
                for (p, blk) in r.condensed {
                    match &mut condensed[p] {
                        Some(s) => *s += &blk,
                        None => condensed[p] = Some(blk),
                    }
                }
            }
        }
        mem.products = peak_rss_kib();
        let theta = recover::thetas(&l2, nb);
        let kept_pos: std::collections::HashMap<usize, usize> =
            boundary.iter().enumerate().map(|(i, &d)| (d, i)).collect();
        let iface_pos: std::collections::HashMap<usize, usize> = interface
            .map(|f| f.dofs.iter().enumerate().map(|(i, &d)| (d, i)).collect())
            .unwrap_or_default();
        let value = |d: usize| -> Vec<Real> {
            let mut v = vec![0.0; nr];
            if int_of[d] != usize::MAX {
                let i = int_of[d];
                for c in 0..nb {
                    v[c] = psi[(i, c)];
                }
                for c in 0..nq {
                    v[nb + c] = phi[(i, c)];
                }
            } else if let Some(&p) = kept_pos.get(&d) {
                v[p] = 1.0;
            } else if let (Some(&p), Some(f)) = (iface_pos.get(&d), interface) {
                for c in 0..f.n_coords() {
                    v[boundary.len() + c] = f.basis[(p, c)];
                }
            }
            v
        };
        let mut sep_est: Vec<Vec<Real>> = vec![Vec::new(); pieces.len()];
        for (g, grp) in groups.iter().enumerate() {
            let Kind::Separator(p) = grp.kind else {
                continue;
            };
            let (Some(sum), Some(cond)) = (schur[p].take(), condensed[p].take()) else {
                continue;
            };
            sep_est[p] = recover::separator(
                k,
                m,
                &groups[g],
                sum,
                schur_count[p],
                cond,
                &value,
                &theta,
                l2.k.as_ref(),
            )?;
        }
        recovery_s += t.elapsed().as_secs_f64();

        // The verdict: per column, the sum of the estimates; per unit, its largest.
        let total: Vec<Real> = (0..nr)
            .map(|c| {
                sub_est
                    .iter()
                    .chain(&sep_est)
                    .map(|e| e.get(c).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect();
        let max_over = |e: &[Real], modes: bool| -> Real {
            let range = if modes { nb..nr } else { 0..nb };
            e.get(range)
                .map_or(0.0, |s| s.iter().fold(0.0, |a: Real, &x| a.max(x)))
        };
        let est_modes = max_over(&total, true);
        let est_static = max_over(&total, false);
        let converged = est_modes <= sub.tol && est_static <= sub.tol;
        // Greedy: the units (substructures, pieces) with the largest estimates are refined
        // until what the others leave is below half the tolerance in every column.
        let mut redo_subs: Vec<usize> = Vec::new();
        let mut redo_pieces: Vec<usize> = Vec::new();
        if !converged && rounds <= sub.max_rounds {
            let mut units: Vec<(Real, bool, usize)> = (0..subs_dofs.len())
                .map(|j| {
                    (
                        max_over(&sub_est[j], true).max(max_over(&sub_est[j], false)),
                        true,
                        j,
                    )
                })
                .chain(
                    (0..pieces.len())
                        .filter(|&p| degrees[p] < sub.max_degree)
                        .map(|p| {
                            (
                                max_over(&sep_est[p], true).max(max_over(&sep_est[p], false)),
                                false,
                                p,
                            )
                        }),
                )
                .collect();
            units.sort_by(|a, b| b.0.total_cmp(&a.0));
            let mut left = total.clone();
            for (_, is_sub, u) in units {
                let worst = |l: &[Real]| max_over(l, true).max(max_over(l, false));
                if worst(&left) <= 0.5 * sub.tol {
                    break;
                }
                let e = if is_sub { &sub_est[u] } else { &sep_est[u] };
                for (l, x) in left.iter_mut().zip(e) {
                    *l -= x;
                }
                if is_sub {
                    redo_subs.push(u);
                } else {
                    redo_pieces.push(u);
                }
            }
        }
        if !redo_subs.is_empty() || !redo_pieces.is_empty() {
            drop(subs);
            for j in redo_subs {
                cutoffs[j] *= 1.6f64.powi(2);
                level1[j] = None;
            }
            for p in redo_pieces {
                degrees[p] = (degrees[p] + 2).min(sub.max_degree);
                let g = groups
                    .iter()
                    .position(|g| g.kind == Kind::Separator(p))
                    .expect("piece group");
                groups[g].basis = groups::separator_basis(&pieces[p], coords, degrees[p])?;
                for l in level1.iter_mut() {
                    if l.as_ref().is_some_and(|l| l.adj.contains(&g)) {
                        *l = None;
                    }
                }
            }
            continue;
        }

        // The model.
        let multilevel = MultilevelStats {
            substructures: (0..subs_dofs.len())
                .map(|j| {
                    let l = subs[j];
                    SubstructureStats {
                        n_dofs: subs_dofs[j].len(),
                        n_neighbours: l.adj.len(),
                        n_coupling_coords: l.kcc.nrows(),
                        n_modes: l.mu.len(),
                        cutoff_hz: l.cutoff.sqrt() / (2.0 * PI),
                        factor_nnz: sub_nnz[j],
                        estimate_modes: max_over(&sub_est[j], true),
                        estimate_static: max_over(&sub_est[j], false),
                    }
                })
                .collect(),
            separators: (0..pieces.len())
                .map(|p| SeparatorStats {
                    n_dofs: pieces[p].len(),
                    depth: s.separator_depth[p],
                    degree: degrees[p],
                    n_coords: groups
                        .iter()
                        .find(|g| g.kind == Kind::Separator(p))
                        .map_or(0, Group::n_coords),
                    estimate_modes: max_over(&sep_est[p], true),
                    estimate_static: max_over(&sep_est[p], false),
                })
                .collect(),
            level2_sizes: l2.sizes,
            rounds,
            tol: sub.tol,
            estimate_modes: est_modes,
            estimate_static: est_static,
            converged,
            substructuring_s,
            level1_s,
            level2_s,
            recovery_s,
        };
        let factor_nnz = sub_nnz.iter().copied().max().unwrap_or(0);
        let stats = CbStats {
            n_dofs: n,
            n_boundary: nb,
            n_interface_dofs: interface.map_or(0, |f| f.dofs.len()),
            n_interface_coords: interface.map_or(0, |f| f.n_coords()),
            n_interior: interior.len(),
            n_modes: nq,
            nnz_kii: 0,
            frequency_of_interest_hz: opts.frequency_of_interest_hz,
            cutoff_hz: opts.resolved_cutoff_hz(),
            eigen_method: EigenMethod::Substructured,
            krylov_dim: 0,
            n_solves: 0,
            partition_s: substructuring_s,
            ordering: super::factor::KiiOrdering::NestedDissection,
            ordering_s: 0.0,
            factor_nnz,
            factor_s: 0.0,
            constraint_modes_s: 0.0,
            eigen_s: level1_s + level2_s,
            eigen_solve_s: 0.0,
            eigen_orth_s: 0.0,
            eigen_qr_s: 0.0,
            products_s: recovery_s,
            total_s: t_start.elapsed().as_secs_f64(),
            peak_rss_kib: mem,
            multilevel: Some(multilevel),
        };
        return Ok(CbModel {
            fixed_frequencies_hz: l2
                .lambda
                .iter()
                .map(|&l| l.max(0.0).sqrt() / (2.0 * PI))
                .collect(),
            k: l2.k,
            m: l2.m,
            b: None,
            boundary: boundary.to_vec(),
            interface: interface.cloned(),
            interior,
            n_modes: nq,
            psi,
            phi,
            n_dofs: n,
            stats,
        });
    }
}

/// The pattern of `a` restricted to `rows` (`local[d]` = position of DOF d in `rows`).
fn sub_pattern(a: &Sparse, rows: &[usize], local: &[usize]) -> SymbolicSparseColMat<usize> {
    let mut ptr = Vec::with_capacity(rows.len() + 1);
    ptr.push(0);
    let mut idx = Vec::new();
    for &d in rows {
        let start = idx.len();
        idx.extend(
            a.row_idx_of_col_raw(d)
                .iter()
                .filter(|&&i| local[i] != usize::MAX)
                .map(|&i| local[i]),
        );
        idx[start..].sort_unstable();
        ptr.push(idx.len());
    }
    SymbolicSparseColMat::new_checked(rows.len(), rows.len(), ptr, None, idx)
}
