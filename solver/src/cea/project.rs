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
        let same_k = first_difference(&sys.k, &self.k_ref).is_none();
        let same_b = match (&sys.b, &self.b_ref) {
            (Some(b), Some(b0)) => first_difference(b, b0).is_none(),
            (None, None) => true,
            _ => false,
        };
        if let (true, true, true, Some(bl), Some(d)) =
            (same_m, same_k, same_b, &self.blocks, &sys.d)
        {
            if ng > 0 {
                let (k_p, c_p) = self.galerkin_blocks(bl, d, sys.c_f.as_ref())?;
                return self.finish(n, ng, t0, k_p, c_p, None, opts);
            }
        }
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
        let kpsi = if same_k {
            self.kpsi.clone()
        } else {
            &sys.k * psi
        };
        let bpsi = match (&sys.b, &self.b_ref, &self.bpsi) {
            (Some(_), Some(_), Some(bp)) if same_b => Some(bp.clone()),
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
        self.finish(n, ng, t0, k_p, c_p, llt.as_ref(), opts)
    }

    /// The projected roots of `η̈ + C_p η̇ + K_p η = 0` (after the Cholesky sandwich when M
    /// changed: `llt`), their shapes `Ψ L⁻ᵀ w` and the statistics.
    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        n: usize,
        ng: usize,
        t0: Instant,
        k_p: Mat<f64>,
        c_p: Option<Mat<f64>>,
        llt: Option<&faer::linalg::solvers::Llt<f64>>,
        opts: &CeaOptions,
    ) -> Result<CeaResult, CeaError> {
        let psi = &self.psi;
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
            Some(w) => recover_shapes(w, llt.map(|l| l.L()), Some(psi)),
            None => vec![Vec::new(); fo.vals.len()],
        };
        let modes = make_modes(&fo.vals, shapes, fo.rho, opts);
        finish_stats(&mut stats, &modes, fo.rho);
        stats.time_eigen_s = t1.elapsed().as_secs_f64();
        Ok(CeaResult { modes, stats })
    }

    /// `K_p = ΨᵀPKΨ` and `C_p = ΨᵀPCΨ` from the μ-independent [`Blocks`] (K, B, M and G those
    /// of the reference state): only the products with D and C_f are made.
    ///
    /// # Derivation
    /// With `P = I − A S⁻¹Yᵀ`, `A = Gᵀ − D`, `S = YᵀA`,
    /// ```text
    /// ΨᵀPXΨ = ΨᵀXΨ − (ΨᵀA) S⁻¹ (YᵀXΨ),
    /// ```
    /// and with `W = [Ψ, Y]` the four blocks are the rows of `WᵀXΨ` and `WᵀA = WᵀGᵀ − WᵀD`
    /// (its lower block is S). `WᵀKΨ`, `WᵀBΨ` and `WᵀGᵀ` are made once; per solve
    /// `WᵀD` ((nb + ng) × n × ng), `C_fΨ` and `Wᵀ(C_fΨ)`, an LU of S (ng × ng) and two
    /// small products, instead of `YᵀA`, `P KΨ`, `P CΨ` (each `Yᵀ X Ψ` and `A (S⁻¹ ·)` of size
    /// n) and `Ψᵀ(P XΨ)` — the same matrices to round-off (`project::tests`).
    #[allow(non_snake_case)]
    fn galerkin_blocks(
        &self,
        bl: &super::basis::Blocks,
        D: &Mat<f64>,
        c_f: Option<&Mat<f64>>,
    ) -> Result<(Mat<f64>, Option<Mat<f64>>), CeaError> {
        let nb = self.psi.ncols();
        let ng = D.ncols();
        let wt = bl.w.transpose();
        let wa = &bl.wg - wt * D;
        let s = wa.subrows(nb, ng).to_owned();
        let lu = s.partial_piv_lu();
        let pr = super::operator::pivot_ratio(lu.U(), |x: &f64| x.abs());
        if pr.is_nan() || pr <= 1e3 * f64::EPSILON {
            return Err(CeaError::SingularContactOperator { ng, ratio: pr });
        }
        let psi_a = wa.subrows(0, nb);
        let galerkin = |wx: Mat<f64>| -> Mat<f64> {
            let mut low = wx.subrows(nb, ng).to_owned();
            faer::linalg::solvers::Solve::solve_in_place(&lu, &mut low);
            wx.subrows(0, nb) - psi_a * &low
        };
        let k_p = galerkin(bl.wk.clone());
        let wcf = c_f.map(|c| wt * (c * &self.psi));
        let wc = match (&bl.wb, wcf) {
            (None, None) => None,
            (Some(wb), None) => Some(wb.clone()),
            (None, Some(w)) => Some(-w),
            (Some(wb), Some(w)) => Some(wb - w),
        };
        Ok((k_p, wc.map(galerkin)))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cea::test_random::{random_spd, Rng};
    use crate::cea::{Cplx, ProjectionOptions};

    /// 40 DOFs, 6 constraints, B, and the friction terms D = μ D1, C_f = μ C1 (K, M, B, G the
    /// same at every μ, as in a friction sweep).
    fn model(mu: f64) -> CeaMatrices {
        let (n, ng) = (40, 6);
        let mut rng = Rng(3);
        let mut spd = |shift: f64| random_spd(n, &mut rng, shift);
        let m = spd(n as f64);
        let mut k = spd(0.0);
        for i in 0..n {
            k[(i, i)] += n as f64 * (1.0 + 100.0 * (i as f64 / n as f64).powi(2));
        }
        let mut rng = Rng(17);
        let g = Mat::from_fn(ng, n, |_, _| rng.next());
        let d1 = Mat::from_fn(n, ng, |_, _| 0.3 * rng.next());
        let c1 = Mat::from_fn(n, n, |_, _| 0.05 * rng.next());
        let mut s = CeaMatrices::new(m.clone(), k.clone());
        s.b = Some(&k * 1e-4 + &m * 1e-3);
        s.g = Some(g);
        s.d = Some(&d1 * mu);
        s.c_f = Some(&c1 * mu);
        s
    }

    /// Largest |p_a − p_b|/|p_b| over the roots of two solves, paired in order (both sorted
    /// by frequency; the same matrices to round-off give the same order).
    fn max_rel_diff(a: &CeaResult, b: &CeaResult) -> f64 {
        assert_eq!(a.modes.len(), b.modes.len());
        a.modes
            .iter()
            .zip(&b.modes)
            .map(|(x, y)| (x.eigenvalue - y.eigenvalue).norm() / y.eigenvalue.norm())
            .fold(0.0, f64::max)
    }

    /// The projection from the μ-independent blocks (`galerkin_blocks`) gives the roots of
    /// the direct projection (`P K Ψ`, `P C Ψ` formed at each μ) to round-off, before and
    /// after the basis is enriched; and the roots differ between the μ (the friction terms
    /// enter).
    #[test]
    fn block_projection_equals_the_direct_projection() {
        let opts = CeaOptions {
            method: CeaMethod::Projection,
            projection: ProjectionOptions {
                n_basis: Some(14),
                ..ProjectionOptions::default()
            },
            ..CeaOptions::default()
        };
        let mut basis = ModalBasis::new(&model(0.0), &opts).unwrap();
        assert!(basis.blocks.is_some());
        for round in 0..2 {
            let mut direct = basis.clone();
            direct.blocks = None;
            let r0 = basis.solve(&model(0.2), &opts).unwrap();
            for mu in [0.2, 0.7] {
                let sys = model(mu);
                let (a, b) = (
                    basis.solve(&sys, &opts).unwrap(),
                    direct.solve(&sys, &opts).unwrap(),
                );
                let d = max_rel_diff(&a, &b);
                eprintln!(
                    "round {round}, mu {mu}: nb {}, max rel diff {d:.1e}",
                    basis.len()
                );
                assert!(d <= 1e-12, "mu {mu}: {d:e}");
                // Shapes: the same vectors (unit norm, same phase convention).
                for (x, y) in a.modes.iter().zip(&b.modes) {
                    let e = x
                        .shape
                        .iter()
                        .zip(&y.shape)
                        .map(|(p, q)| (p - q).norm())
                        .fold(0.0, f64::max);
                    assert!(e <= 1e-9, "mu {mu}: shape {e:e}");
                }
                if mu != 0.2 {
                    assert!(max_rel_diff(&a, &r0) > 1e-6);
                }
            }
            // Enrich with two arbitrary vectors: the blocks are made again.
            let mut rng = Rng(99 + round);
            let v: Vec<Vec<Cplx>> = (0..2)
                .map(|_| (0..40).map(|_| Cplx::new(rng.next(), rng.next())).collect())
                .collect();
            assert_eq!(basis.enrich(&v, 1e-6).unwrap(), 4);
        }
    }
}
