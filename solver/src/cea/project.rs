//! Projected complex eigenvalue analysis on a fixed real modal basis.

use super::eigen::{finish_stats, make_modes, recover_shapes, sandwich};
use super::first_order::first_order_eigen;
use super::operator::{check_inputs, cholesky, mass_solve, ContactProjector};
use super::refine::refine;
use super::{CeaError, CeaMatrices, CeaMethod, CeaOptions, CeaResult, CeaStats, ModalBasis};
use faer::Mat;
use std::time::Instant;

/// First entry where `a` and `b` differ (shapes assumed equal).
fn first_difference(a: &Mat<f64>, b: &Mat<f64>) -> Option<(usize, usize)> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if a[(i, j)] != b[(i, j)] {
                return Some((i, j));
            }
        }
    }
    None
}

impl ModalBasis {
    /// True when `sys` has this basis' reference K, M and G (entry for entry): a basis made
    /// afresh from `sys` with the same options would be this one ([`ModalBasis::new`] reads
    /// nothing else), so reusing it for `sys` is no approximation.
    pub fn is_basis_of(&self, sys: &CeaMatrices) -> bool {
        let same = |a: &Mat<f64>, b: &Mat<f64>| {
            a.nrows() == b.nrows() && a.ncols() == b.ncols() && first_difference(a, b).is_none()
        };
        let g = match (&sys.g, &self.g_ref) {
            (Some(a), Some(b)) => same(a, b),
            (None, None) => true,
            _ => false,
        };
        g && same(&sys.k, &self.k_ref) && same(&sys.m, &self.m_ref)
    }

    /// Complex eigenvalue analysis of `sys` projected on the basis: the roots of the
    /// constrained problem restricted to `u = Ψ η` (nb of them, one per conjugate pair kept).
    ///
    /// # Reference
    /// Subspace projection of [Paper eqs. (19)–(24)] as in Abaqus's complex eigenvalue
    /// extraction; the constraint and multipliers are eliminated as in [`super::reduce`].
    ///
    /// # Derivation
    /// `G Ψ = 0`, so `u = Ψ η` satisfies the constraint, and with the contact projector P of
    /// [`super::reduce`] (`P M Ψ = M Ψ` since `G M⁻¹ M Ψ = 0`) the Galerkin equations
    /// `Ψᵀ P (M Ψ η̈ + C Ψ η̇ + K Ψ η) = 0` give
    /// ```text
    /// M_p = ΨᵀMΨ (= I for the reference M),   C_p = ΨᵀPCΨ,   K_p = ΨᵀPKΨ     (nb × nb)
    /// ```
    /// With `Ψ = T Φ` these are `ΦᵀM_rΦ`, `ΦᵀC_rΦ`, `ΦᵀK_rΦ`: with the full basis Φ is
    /// invertible and the roots are exactly those of the reduced problem; truncated, the
    /// roots well below the cutoff are approximated (the error is what a sweep's exact
    /// checks measure). Per call: products of K, C and M with Ψ (O(n² nb); K Ψ and B Ψ are
    /// reused when K and B are those of the reference state, as in a friction sweep) and a
    /// dense eigenproblem of size 2 nb; no factorisation of size n unless M changed.
    ///
    /// # Errors
    /// Matrix sizes or G differing from the reference ([`CeaError::BasisMismatch`]), the
    /// errors of the input checks, a singular contact operator, non-convergence.
    #[allow(non_snake_case)]
    pub fn solve(&self, sys: &CeaMatrices, opts: &CeaOptions) -> Result<CeaResult, CeaError> {
        let t0 = Instant::now();
        let (n, ng) = check_inputs(sys)?;
        let psi = &self.psi;
        let ng_ref = self.g_ref.as_ref().map_or(0, |g| g.nrows());
        if n != psi.nrows() || ng != ng_ref {
            return Err(CeaError::Shape {
                what: "problem projected on the basis (n, ng)",
                rows: n,
                cols: ng,
                expected_rows: psi.nrows(),
                expected_cols: ng_ref,
            });
        }
        if let (Some(g), Some(g0)) = (&sys.g, &self.g_ref) {
            if let Some((i, j)) = first_difference(g, g0) {
                return Err(CeaError::BasisMismatch {
                    what: "G",
                    row: i,
                    col: j,
                    value: g[(i, j)],
                    reference: g0[(i, j)],
                });
            }
        }
        let same_m = first_difference(&sys.m, &self.m_ref).is_none();
        let m_p = (!same_m).then(|| psi.transpose() * (&sys.m * psi));
        let project = match (&sys.d, &self.gt) {
            (Some(D), Some(Gt)) if ng > 0 => {
                let Y = match (&self.y, same_m) {
                    (Some(y), true) => y.clone(),
                    _ => mass_solve(&sys.m, Gt)?,
                };
                Some(ContactProjector::new(Y, Gt, D)?)
            }
            _ => None,
        };
        let galerkin = |XPsi: Mat<f64>| -> Mat<f64> {
            let PXPsi = match &project {
                Some(p) => p.apply(XPsi),
                None => XPsi,
            };
            psi.transpose() * PXPsi
        };
        // K Ψ and B Ψ of the reference state are reused when K and B are the same.
        let kpsi = if first_difference(&sys.k, &self.k_ref).is_none() {
            self.kpsi.clone()
        } else {
            &sys.k * psi
        };
        let bpsi = match (&sys.b, &self.b_ref, &self.bpsi) {
            (Some(b), Some(b0), Some(bp)) if first_difference(b, b0).is_none() => Some(bp.clone()),
            (Some(b), _, _) => Some(b * psi),
            (None, _, _) => None,
        };
        let mut k_p = galerkin(kpsi);
        let c_psi = match (bpsi, &sys.c_f) {
            (None, None) => None,
            (Some(bp), None) => Some(bp),
            (None, Some(c)) => Some(-(c * psi)),
            (Some(bp), Some(c)) => Some(bp - c * psi),
        };
        let mut c_p = c_psi.map(galerkin);
        let llt = match &m_p {
            Some(mp) => Some(cholesky("Psi^T M Psi", mp)?),
            None => None,
        };
        if let Some(llt) = &llt {
            k_p = sandwich(llt.L(), &k_p);
            c_p = c_p.map(|c| sandwich(llt.L(), &c));
        }
        let mut stats = CeaStats {
            n,
            n_constraints: ng,
            n_reduced: self.n_reduced,
            method: CeaMethod::Projection,
            n_basis: self.len(),
            basis_max_frequency_hz: self.frequencies_hz().last().copied(),
            constraint_rank_ratio: self.rank_ratio,
            time_reduce_s: t0.elapsed().as_secs_f64(),
            ..CeaStats::default()
        };
        let t1 = Instant::now();
        let fo = first_order_eigen(&k_p, c_p.as_ref(), opts.compute_shapes)?;
        let shapes = match fo.w {
            Some(w) => recover_shapes(w, llt.as_ref().map(|l| l.L()), Some(psi)),
            None => vec![Vec::new(); fo.vals.len()],
        };
        let modes = make_modes(&fo.vals, shapes, fo.rho, opts);
        finish_stats(&mut stats, &modes, fo.rho);
        stats.time_eigen_s = t1.elapsed().as_secs_f64();
        Ok(CeaResult { modes, stats })
    }

    /// The band whose roots the projection is meant to give: `projection.frequency_max_hz`,
    /// else the highest basis frequency / `cutoff_factor`, Hz.
    pub fn band_hz(&self, opts: &CeaOptions) -> f64 {
        let pr = &opts.projection;
        let f_max = self.frequencies_hz().last().copied().unwrap_or(0.0);
        pr.frequency_max_hz.unwrap_or(f_max / pr.cutoff_factor)
    }

    /// [`ModalBasis::solve`], then (with `projection.refine.enabled`) every unstable root with
    /// frequency ≤ [`ModalBasis::band_hz`] refined exactly by shift-invert Arnoldi on the full
    /// first-order operator of `sys` — no constraint elimination, no projection (statistics
    /// in [`CeaStats::refine`]: targets, shifts, |p_exact − p_projected|, residuals).
    ///
    /// # Errors
    /// As [`ModalBasis::solve`]; a refinement shift that is a root to machine precision.
    pub fn solve_refined(
        &self,
        sys: &CeaMatrices,
        opts: &CeaOptions,
    ) -> Result<CeaResult, CeaError> {
        let mut r = self.solve(sys, opts)?;
        let ro = &opts.projection.refine;
        if ro.enabled {
            let tol = opts.unstable_tol * r.stats.spectral_radius;
            let st = refine(
                sys,
                &mut r.modes,
                self.band_hz(opts),
                tol,
                ro,
                &opts.interrupt,
            )?;
            let rho = r.stats.spectral_radius;
            finish_stats(&mut r.stats, &r.modes, rho);
            r.stats.time_eigen_s += st.time_s;
            r.stats.refine = Some(st);
        }
        Ok(r)
    }
}
