//! Verification of a reduced model against its full component without a second eigen-solve:
//! one LDLᵀ factorisation of K − σM at the top of the checked band gives the exact number of
//! full-component modes below σ (Sylvester's law of inertia, the Sturm count), and a few
//! shift-invert solves with that factor refine the reduced model's modes, expanded to the full
//! component, into converged full-component modes (Rayleigh–Ritz on [X, AX, A²X],
//! A = (K − σM)⁻¹M).
//!
//! # Why the refined values are the full model's
//! The reduced modes X span the full modes below the band up to the reduction error, which
//! lives in directions the reduction dropped: fixed-interface modes above the cut-off (and, with
//! an interface basis, interface shapes it cannot represent). Each application of A damps a
//! component with eigenvalue μ relative to one with λ by |λ − σ|/|μ − σ|; with the cut-off at
//! twice the band (μ ≥ 4σ) that is ≤ 1/3 for every λ ≤ σ, and Rayleigh–Ritz on the block Krylov
//! space [X, AX, A²X] converges faster still. The refined Ritz vectors' residuals are reported:
//! they bound what is left.
//!
//! # Reference
//! Sturm count by inertia: Grimes, Lewis & Simon, "A shifted block Lanczos algorithm for
//! solving sparse symmetric generalized eigenproblems", SIAM J. Matrix Anal. Appl. 15 (1994)
//! 228–272, §2; Ericsson & Ruhe (1980) for the spectral transformation.

use super::model::CbModel;
use super::partition::{at_b, sym_spmm, Sparse};
use super::rigid::DofPoint;
use crate::error::ReductionError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLdltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::{Conj, Mat, MatMut, MatRef, Par, Side, Spec};
use rayon::prelude::*;
use serde::Serialize;
use squeal_fe::ordering::{nested_dissection, NestedDissectionOptions};
use squeal_meshes::Real;
use std::time::Instant;

/// What the verification found (part of [`CbCheck`](super::CbCheck)).
#[derive(Debug, Clone, Serialize)]
pub struct Verification {
    /// The shift σ = (2π f)², f in Hz: the top of the checked band.
    pub shift_hz: Real,
    /// Full-component modes below the shift: negative pivots of the LDLᵀ of K − σM.
    pub n_full_below: usize,
    /// Reduced-model modes below the shift.
    pub n_reduced_below: usize,
    /// Refined modes below the shift (≤ `n_full_below`; fewer means modes the reduced model's
    /// subspace does not contain).
    pub n_refined_below: usize,
    /// Reduced modes refined (those below 1.3 × the shift in frequency).
    pub n_refined: usize,
    /// Right-hand sides solved with the factor.
    pub n_solves: usize,
    /// Shift-invert steps (each one solve per refined mode, then Rayleigh–Ritz), until the
    /// refined modes' residual reached 1e-6, or, from the second step on, their frequencies
    /// moved by less than `frequency_tol` in the last step; at most 4.
    pub steps: usize,
    /// Largest relative change of a refined frequency below the shift in the last step: the
    /// estimate of the refined frequencies' error (each step reduces the error of a mode
    /// below the shift by |λ − σ|/|μ − σ| ≤ 1/3 for the components the reduction dropped,
    /// so the error left after a step is at most half the change it made). None when no step
    /// was taken.
    pub frequency_change: Option<Real>,
    /// The relative frequency accuracy the refinement stopped at (the check's frequency
    /// tolerance × 1e-3: no verdict of the check can turn on a smaller error).
    pub frequency_tol: Real,
    /// Largest relative residual ‖Kx − λMx‖ / max(‖Kx‖, σ‖Mx‖) of the refined modes below the
    /// shift: the refined values are the full model's to about this squared.
    pub max_refined_residual: Real,
    /// Largest |A_ii / D_ii| of the LDLᵀ (a large value means a pivot close to singular).
    pub max_pivot_ratio: Real,
    /// Stored entries of the factor.
    pub factor_nnz: usize,
    /// Seconds: ordering and factorisation, solves and Rayleigh–Ritz.
    pub factor_s: Real,
    pub refine_s: Real,
}

/// Refined full-component frequencies (Hz, ascending, those below the shift) and the
/// verification record. `reduced` = the reduced model's eigenpairs (values ascending, vectors
/// M_r-orthonormal), `points` give DOF coordinates for a nested-dissection ordering.
pub(crate) fn verify(
    model: &CbModel,
    k: &Sparse,
    m: &Sparse,
    reduced: (&[Real], MatRef<'_, Real>),
    foi_hz: Real,
    points: Option<&[DofPoint]>,
    frequency_tol: Real,
) -> Result<(Vec<Real>, Verification), ReductionError> {
    let two_pi = 2.0 * std::f64::consts::PI;
    let (red_vals, red_vecs) = reduced;
    let mut sigma = (two_pi * foi_hz).powi(2);
    // Keep σ off the reduced eigenvalues (the full ones lie just below them).
    for _ in 0..20 {
        match red_vals
            .iter()
            .find(|&&l| ((l - sigma) / sigma).abs() < 1e-3)
        {
            Some(&l) => sigma = l * (1.0 + 2e-3),
            None => break,
        }
    }
    let n = k.nrows();
    let t0 = Instant::now();
    let factor = ShiftedLdlt::new(k, m, sigma, points)?;
    let factor_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let n_reduced_below = red_vals.iter().filter(|&&l| l < sigma).count();
    let sel: Vec<usize> = (0..red_vals.len())
        .filter(|&i| red_vals[i] < 1.69 * sigma)
        .collect();
    let mut n_solves = 0;
    let mut steps = 0;
    let mut frequency_change = None;
    let (refined_vals, max_res, n_refined_below) = if sel.is_empty() {
        (Vec::new(), 0.0, 0)
    } else {
        let y = Mat::<Real>::from_fn(red_vecs.nrows(), sel.len(), |r, c| red_vecs[(r, sel[c])]);
        let mut basis = Basis::new(k, m);
        basis.extend(model.expand(y.as_ref()));
        let mut previous: Vec<Real> = Vec::new();
        loop {
            let (vals, x, kx, mx) = basis.ritz()?;
            // The largest relative frequency change of the modes below σ in this step.
            if steps > 0 {
                let change = vals
                    .iter()
                    .zip(&previous)
                    .filter(|(&l, _)| l < sigma)
                    .map(|(&l, &l0)| {
                        let (f, f0) = (l.max(0.0).sqrt(), l0.max(0.0).sqrt());
                        (f - f0).abs() / f.max(Real::MIN_POSITIVE)
                    })
                    .fold(0.0, Real::max);
                frequency_change = Some(change);
            }
            previous = vals.clone();
            let mut max_res: Real = 0.0;
            for (c, &l) in vals.iter().enumerate() {
                if l >= sigma {
                    break;
                }
                let (mut r2, mut k2, mut m2) = (0.0, 0.0, 0.0);
                for i in 0..n {
                    let (a, b) = (kx[(i, c)], mx[(i, c)]);
                    r2 += (a - l * b).powi(2);
                    k2 += a * a;
                    m2 += b * b;
                }
                let res = r2.sqrt() / k2.sqrt().max(sigma * m2.sqrt()).max(Real::MIN_POSITIVE);
                max_res = max_res.max(res);
            }
            let settled = steps >= 2 && frequency_change.is_some_and(|c| c <= frequency_tol);
            if max_res <= REFINED_RESIDUAL || settled || steps == MAX_STEPS {
                let below = vals.iter().filter(|&&l| l < sigma).count();
                break (vals, max_res, below);
            }
            // Shift-invert step on the Ritz vectors of the selected modes.
            let count = vals.iter().filter(|&&l| l < 1.69 * sigma).count().max(1);
            let mut w = mx.subcols(0, count).to_owned();
            drop((x, kx, mx));
            factor.solve(w.as_mut());
            n_solves += count;
            steps += 1;
            basis.extend(w);
        }
    };
    let hz: Vec<Real> = refined_vals
        .iter()
        .filter(|&&l| l < sigma)
        .map(|&l| l.max(0.0).sqrt() / two_pi)
        .collect();
    Ok((
        hz,
        Verification {
            shift_hz: sigma.sqrt() / two_pi,
            n_full_below: factor.n_negative,
            n_reduced_below,
            n_refined_below,
            n_refined: sel.len(),
            n_solves,
            steps,
            frequency_change,
            frequency_tol,
            max_refined_residual: max_res,
            max_pivot_ratio: factor.max_pivot_ratio,
            factor_nnz: factor.vals.len(),
            factor_s,
            refine_s: t1.elapsed().as_secs_f64(),
        },
    ))
}

fn sym(a: Mat<Real>) -> Mat<Real> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// Steps after the reduced modes themselves, and the residual at which the refinement stops.
const MAX_STEPS: usize = 4;
const REFINED_RESIDUAL: Real = 1e-6;

/// An M-orthonormal basis Q with K Q and M Q, grown block by block: two passes of Gram–Schmidt
/// against Q, then an eigen-decomposition of the block's Gram matrix keeping directions above
/// 1e-10 of its largest (Stathopoulos & Wu's SVQB).
struct Basis<'a> {
    k: &'a Sparse,
    m: &'a Sparse,
    q: Mat<Real>,
    kq: Mat<Real>,
    mq: Mat<Real>,
}

impl<'a> Basis<'a> {
    fn new(k: &'a Sparse, m: &'a Sparse) -> Self {
        let n = k.nrows();
        Basis {
            k,
            m,
            q: Mat::zeros(n, 0),
            kq: Mat::zeros(n, 0),
            mq: Mat::zeros(n, 0),
        }
    }

    fn extend(&mut self, mut w: Mat<Real>) {
        let n = w.nrows();
        for _ in 0..2 {
            if self.q.ncols() > 0 {
                let c = at_b(self.mq.as_ref(), w.as_ref());
                w -= &self.q * &c;
            }
        }
        let mw = sym_spmm(self.m, w.as_ref());
        let g = sym(at_b(w.as_ref(), mw.as_ref()));
        let Ok(evd) = g.self_adjoint_eigen(Side::Lower) else {
            return;
        };
        let s = evd.S().column_vector();
        let smax = (0..s.nrows()).map(|i| s[i]).fold(0.0, Real::max);
        let keep: Vec<usize> = (0..s.nrows()).filter(|&i| s[i] > 1e-10 * smax).collect();
        if keep.is_empty() {
            return;
        }
        let u = evd.U();
        let t = Mat::<Real>::from_fn(w.ncols(), keep.len(), |r, c| {
            u[(r, keep[c])] / s[keep[c]].sqrt()
        });
        let (nw, nmw) = (&w * &t, &mw * &t);
        let nkw = sym_spmm(self.k, nw.as_ref());
        let c0 = self.q.ncols();
        let c1 = c0 + keep.len();
        for (dst, src) in [
            (&mut self.q, &nw),
            (&mut self.mq, &nmw),
            (&mut self.kq, &nkw),
        ] {
            dst.resize_with(n, c1, |_, _| 0.0);
            dst.subcols_mut(c0, keep.len()).copy_from(src);
        }
    }

    /// Rayleigh–Ritz: values ascending, and X, K X, M X of the Ritz vectors.
    #[allow(clippy::type_complexity)]
    fn ritz(&self) -> Result<(Vec<Real>, Mat<Real>, Mat<Real>, Mat<Real>), ReductionError> {
        let kh = sym(at_b(self.q.as_ref(), self.kq.as_ref()));
        let mh = sym(at_b(self.q.as_ref(), self.mq.as_ref()));
        let (vals, z) = super::eigen::dense_all(kh.as_ref(), mh.as_ref(), "refinement")?;
        Ok((vals, &self.q * &z, &self.kq * &z, &self.mq * &z))
    }
}

/// LDLᵀ of K − σM (no pivoting, supernodal; nested-dissection order with DOF coordinates,
/// AMD otherwise) with its inertia.
struct ShiftedLdlt {
    sym: SymbolicCholesky<usize>,
    vals: Vec<Real>,
    n_negative: usize,
    max_pivot_ratio: Real,
}

impl ShiftedLdlt {
    fn new(
        k: &Sparse,
        m: &Sparse,
        sigma: Real,
        points: Option<&[DofPoint]>,
    ) -> Result<Self, ReductionError> {
        let n = k.nrows();
        let fail = |what: &str, e: String| ReductionError::Factorization {
            what: format!("{what} of K − σM for the check (σ = {sigma:e})"),
            n,
            detail: e,
        };
        let a = squeal_fe::shifted(k.as_ref(), m.as_ref(), sigma, true);
        let perm = match points.filter(|p| p.len() == n && n >= 2000) {
            Some(p) => {
                let xyz: Vec<[Real; 3]> = p.iter().map(|d| d.xyz).collect();
                nested_dissection(k.symbolic(), &xyz, &NestedDissectionOptions::default())
                    .ok()
                    .map(|(p, _)| p)
            }
            None => None,
        };
        let ord = match &perm {
            Some(p) => SymmetricOrdering::Custom(PermRef::new_checked(&p.perm, &p.perm_inv, n)),
            None => SymmetricOrdering::Amd,
        };
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let sym = factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ord, params)
            .map_err(|e| fail("symbolic LDLT", format!("{e:?}")))?;
        let mut vals = vec![0.0; sym.len_val()];
        let par = Par::rayon(0);
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
        .map_err(|e| fail("LDLT", format!("{e:?}")))?;
        // D is the diagonal of each supernode's diagonal block; the matrix's diagonal in the
        // factor's order for the pivot ratios.
        let SymbolicCholeskyRaw::Supernodal(s) = sym.raw() else {
            unreachable!("forced supernodal")
        };
        let diag_a: Vec<Real> = (0..n)
            .map(|j| {
                let rows = a.row_idx_of_col_raw(j);
                rows.binary_search(&j)
                    .map(|p| a.val_of_col(j)[p])
                    .unwrap_or(0.0)
            })
            .collect();
        let perm_fwd: Vec<usize> = match &perm {
            Some(p) => p.perm.clone(),
            None => match sym.perm() {
                Some(p) => p.arrays().0.to_vec(),
                None => (0..n).collect(),
            },
        };
        let f = SupernodalLdltRef::new(s, &vals);
        let (mut n_negative, mut max_ratio) = (0usize, 0.0 as Real);
        for sn in 0..s.n_supernodes() {
            let node = f.supernode(sn);
            let mat = node.val();
            for c in 0..mat.ncols() {
                let d = mat[(c, c)];
                if d < 0.0 {
                    n_negative += 1;
                }
                let aj = diag_a[perm_fwd[node.start() + c]];
                max_ratio = max_ratio.max((aj / d).abs());
            }
        }
        if !max_ratio.is_finite() {
            return Err(fail("LDLT", "a zero pivot (σ is an eigenvalue)".into()));
        }
        Ok(ShiftedLdlt {
            sym,
            vals,
            n_negative,
            max_pivot_ratio: max_ratio,
        })
    }

    /// x ← (K − σM)⁻¹ x, columns split over the threads.
    fn solve(&self, x: MatMut<'_, Real>) {
        let threads = rayon::current_num_threads().max(1);
        let chunk = x.ncols().div_ceil(threads).max(1);
        x.par_col_chunks_mut(chunk).for_each(|c| {
            let mut buf =
                MemBuffer::new(self.sym.solve_in_place_scratch::<Real>(c.ncols(), Par::Seq));
            LdltRef::new(&self.sym, &self.vals).solve_in_place_with_conj(
                Conj::No,
                c,
                Par::Seq,
                MemStack::new(&mut buf),
            );
        });
    }
}
