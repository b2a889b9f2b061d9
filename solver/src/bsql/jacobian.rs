//! The iteration matrix of eq. (18) with the u-row eliminated, and its solve.
//!
//! # Reference
//! $$J = \begin{bmatrix} c_j M + B − C_f & c_j (G^T − ∂F_f/∂λ') & K \\ c_j G & 0 & 0 \\
//! −I & 0 & c_j I \end{bmatrix}$$
//! [Paper eq. (18)] (α = cj; the paper's H^T = G^T + ∂F_f/∂λ' is written for F_f on the
//! other side of eq. (8); C_f = ∂F_f/∂v only when `include_friction_damping`).
//!
//! # Derivation (elimination of u)
//! The u-row gives δu = (r_u + δv)/cj. Substituting in the v-row and writing μ = cj δλ / s:
//! $$\begin{bmatrix} A & s(G^T − D) \\ s G & 0 \end{bmatrix}
//! \begin{bmatrix} δv \\ μ \end{bmatrix} =
//! \begin{bmatrix} r_v − K r_u / c_j \\ s\, r_λ / c_j \end{bmatrix},\quad
//! A = c_j M + B − C_f + K / c_j,$$
//! with s = max|A_ii| / max|G_ij| so that both blocks have the same magnitude (the Schur
//! complement s² G A⁻¹ Gᵀ then has pivots of the size of A's, keeping the singularity test
//! meaningful). The (n + ng) system is factorised densely (LU, partial pivoting).
//! For the initial derivatives (cj → ∞ of J/cj) the same layout holds with A = M and
//! right-hand side (r_v, s r_λ), giving δv' = δv, δλ' = s μ, δu' = r_u.
//! An open constraint k (separation, [`super::unilateral`]) has the row F_λk = λ'_k − λ'_open:
//! cj δλ_k = r_λk, i.e. the diagonal entry s²/cj (s² for ∂F/∂y') in place of s G_k.
//! A compliant row (normal contact compliance c_k) keeps s G_k and gets the diagonal
//! −s² c_k cj (see [`super::compliance`] for its right-hand side).
//!
//! # Elimination of the modal block
//! When M, B, K have a diagonal block d that no constraint row touches (the Craig–Bampton
//! modal coordinates; `BsqlSystem::modal`, found by pattern), and the friction tangents D, C_f
//! vanish on its rows and columns (checked at every set-up), the saddle matrix is
//! $$\begin{bmatrix} A_{bb} & A_{bd} & s(G^T − D)_b \\ A_{db} & A_{dd} & 0 \\ s G_b & 0 & C
//! \end{bmatrix},\quad A_{dd} = \mathrm{diag}(c_j M_{ii} + B_{ii} + K_{ii}/c_j),$$
//! and δv_d = A_dd⁻¹ (r_d − A_db δv_b) leaves the (kept + ng) system with
//! S = A_bb − A_bd A_dd⁻¹ A_db in place of A (`linalg::diag_block`). The scaling s is the
//! whole A's (as without elimination), so the two paths differ by round-off only. If a
//! friction tangent touches an eliminated DOF (a contact node's tangential DOFs carry no
//! constraint, so the pattern alone cannot exclude them), the DOFs it touches are marked and
//! the block is found again without them (`BsqlStats::modal_redetections`).
//!
//! # Where a low-rank update would go
//! Only D = ∂F_f/∂λ' (and C_f) change between factorisations at equal cj, and they are
//! non-zero only in the rows of the contact DOFs. Factorising S₀ (the matrix with D = 0)
//! once per cj and applying the Woodbury identity with the rank-(#contact rows) correction
//! in [`BsqlSystem::assemble_iteration_matrix`]/`solve_iteration` would replace the O((n+ng)³)
//! refactorisation by O((n+ng)²·r) work; with cj changing every few steps the gain also needs
//! a cj-independent splitting (e.g. modal coordinates), which is future work.

use faer::Mat;

use super::{BsqlSystem, FrictionForces};
use crate::linalg::diag_block::DiagBlock;
use crate::{Real, SolverError};

/// True when D = ∂F_f/∂λ' has no entry in the rows of the eliminated DOFs, and C_f (if given)
/// none in their rows and columns.
fn tangents_clear(blk: &DiagBlock, d_dlam: &Mat<Real>, cf: Option<&Mat<Real>>) -> bool {
    let ng = d_dlam.ncols();
    let d_ok = blk
        .d
        .iter()
        .all(|&i| (0..ng).all(|k| d_dlam[(i, k)] == 0.0));
    let cf_ok = cf.is_none_or(|cf| {
        blk.d.iter().all(|&i| {
            cf.col_as_slice(i).iter().all(|&x| x == 0.0)
                && (0..cf.ncols()).all(|j| cf[(i, j)] == 0.0)
        })
    });
    d_ok && cf_ok
}

/// The kept block A[kept, kept] of A = cj M + B − C_f + K/cj (M for `cj` = None) into the
/// leading block of `a`.
#[allow(clippy::too_many_arguments)]
fn fill_kept(
    a: &mut Mat<Real>,
    kept: &[usize],
    m: &Mat<Real>,
    b: &Mat<Real>,
    k: &Mat<Real>,
    cf: Option<&Mat<Real>>,
    cj: Option<Real>,
) {
    for (q, &j) in kept.iter().enumerate() {
        let col = &mut a.col_as_slice_mut(q)[..kept.len()];
        let mj = m.col_as_slice(j);
        match cj {
            Some(c) => {
                let inv = 1.0 / c;
                let (bj, kj) = (b.col_as_slice(j), k.col_as_slice(j));
                for (p, &i) in kept.iter().enumerate() {
                    col[p] = c * mj[i] + bj[i] + kj[i] * inv;
                }
                if let Some(cf) = cf {
                    let cfj = cf.col_as_slice(j);
                    for (p, &i) in kept.iter().enumerate() {
                        col[p] -= cfj[i];
                    }
                }
            }
            None => {
                for (p, &i) in kept.iter().enumerate() {
                    col[p] = mj[i];
                }
            }
        }
    }
}

/// A = cj M + B − C_f + K/cj (or M for `cj` = None) into the leading n × n block of `a`;
/// returns max |A_jj|.
struct FillA<'a> {
    a: &'a mut Mat<Real>,
    m: &'a Mat<Real>,
    b: &'a Mat<Real>,
    k: &'a Mat<Real>,
    cf: Option<&'a Mat<Real>>,
    cj: Option<Real>,
    n: usize,
}

impl pulp::WithSimd for FillA<'_> {
    type Output = Real;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Real {
        let n = self.n;
        let mut a_scale: Real = 0.0;
        for j in 0..n {
            let col = &mut self.a.col_as_slice_mut(j)[..n];
            let m = self.m.col_as_slice(j);
            match self.cj {
                Some(c) => {
                    let inv = 1.0 / c;
                    let (b, k) = (self.b.col_as_slice(j), self.k.col_as_slice(j));
                    for i in 0..n {
                        col[i] = c * m[i] + b[i] + k[i] * inv;
                    }
                    if let Some(cf) = self.cf {
                        let cf = cf.col_as_slice(j);
                        for i in 0..n {
                            col[i] -= cf[i];
                        }
                    }
                }
                None => col.copy_from_slice(&m[..n]),
            }
            a_scale = a_scale.max(col[j].abs());
        }
        a_scale
    }
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BsqlSystem<F> {
    /// Fill the saddle matrix for `cj` (None: ∂F/∂y' for the initial conditions); return s.
    pub(crate) fn assemble_iteration_matrix(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        cj: Option<Real>,
    ) -> Result<Real, SolverError> {
        let (n, ng) = (self.n, self.ng);
        if cj.is_some() && self.has_smooth_unilateral() {
            self.update_smooth_slopes(&y[n + ng..]);
        }
        let v = &y[..n];
        let lamp = &yp[n..n + ng];
        // Friction tangents at the current point.
        self.d_dlam.fill(0.0);
        let near_stick = cj.is_some()
            && !self.opts.include_friction_damping
            && self.opts.friction_damping_near_stick
            && self.friction.near_stick(t, v, lamp);
        let after_failure = cj.is_some()
            && !self.opts.include_friction_damping
            && !near_stick
            && self.cf_after_failure;
        let with_cf =
            (self.opts.include_friction_damping || near_stick || after_failure) && cj.is_some();
        if near_stick {
            self.stats.near_stick_factorisations += 1;
        }
        if after_failure {
            self.stats.friction_damping_after_failure += 1;
        }
        if with_cf {
            self.d_dv.fill(0.0);
        }
        self.stats.tangent_evals += 1;
        let d_dv = if with_cf { Some(&mut self.d_dv) } else { None };
        self.friction
            .add_tangents(t, v, lamp, &mut self.d_dlam, d_dv)?;
        while self
            .modal
            .as_ref()
            .is_some_and(|blk| !tangents_clear(blk, &self.d_dlam, with_cf.then_some(&self.d_dv)))
        {
            let cf = with_cf.then_some(&self.d_dv);
            // Friction on an eliminated DOF: keep every DOF the tangents touch, find the block
            // again (the marks only grow, so this ends).
            for i in 0..n {
                let row_d = (0..ng).any(|k| self.d_dlam[(i, k)] != 0.0);
                let row_cf = cf.is_some_and(|cf| {
                    (0..n).any(|j| cf[(i, j)] != 0.0)
                        || cf.col_as_slice(i).iter().any(|&x| x != 0.0)
                });
                self.touched[i] |= row_d || row_cf;
            }
            self.stats.modal_redetections += 1;
            self.set_modal_elimination(true);
        }
        let cf = with_cf.then_some(&self.d_dv);
        let a = &mut self.lu.a;
        let a_scale = match &mut self.modal {
            // A block, column by column on contiguous slices (vectorised).
            None => crate::linalg::sparse::dispatch(FillA {
                a,
                m: &self.M,
                b: &self.B,
                k: &self.K,
                cf,
                cj,
                n,
            }),
            // Kept block, then S = A_bb − A_bd A_dd⁻¹ A_db.
            Some(blk) => {
                fill_kept(a, &blk.kept, &self.M, &self.B, &self.K, cf, cj);
                let (what, coef) = match cj {
                    Some(c) => ("BSQL iteration (eq. 18), modal block", [c, 1.0, 1.0 / c]),
                    None => ("BSQL ∂F/∂y', modal block", [1.0, 0.0, 0.0]),
                };
                blk.fill(&coef, &[&self.M, &self.B, &self.K], what, t)?;
                blk.subtract_schur(a);
                // The whole A's diagonal, as the dense path scales with it.
                let mut a_scale: Real = 0.0;
                for j in 0..n {
                    let ajj = coef[0] * self.M[(j, j)]
                        + coef[1] * self.B[(j, j)]
                        + coef[2] * self.K[(j, j)]
                        - cf.map_or(0.0, |cf| cf[(j, j)]);
                    a_scale = a_scale.max(ajj.abs());
                }
                a_scale
            }
        };
        let s = if a_scale > 0.0 {
            a_scale / self.g_scale
        } else {
            1.0
        };
        // Multiplier blocks; an open constraint's row is cj δλ = r_λ, i.e. (s²/cj) μ = s r_λ/cj
        // with μ = cj δλ/s (and s² μ = s r_λ for ∂F/∂y').
        let d_open = match cj {
            Some(c) => s * s / c,
            None => s * s,
        };
        // Kept position p is DOF dof(p) (all DOFs without elimination).
        let kept = self.modal.as_ref().map(|b| b.kept.as_slice());
        let nv = kept.map_or(n, <[usize]>::len);
        let dof = |p: usize| kept.map_or(p, |kept| kept[p]);
        for k in 0..ng {
            for p in 0..nv {
                let i = dof(p);
                a[(p, nv + k)] = s * (self.G[(k, i)] - self.d_dlam[(i, k)]);
                a[(nv + k, p)] = if self.open[k] {
                    0.0
                } else {
                    s * self.G[(k, i)]
                };
            }
            for l in 0..ng {
                a[(nv + k, nv + l)] = 0.0;
            }
            if self.open[k] {
                a[(nv + k, nv + k)] = d_open;
            }
        }
        self.compliant_matrix_rows(cj, s, nv);
        Ok(s)
    }

    /// Solve with the factorised saddle matrix; `b` = (r_v, r_λ, r_u) becomes (δv, δλ, δu)
    /// (or (δv', δλ', δu') for the derivative matrix, `cj = None`).
    pub(crate) fn solve_iteration(
        &mut self,
        b: &mut [Real],
        cj: Option<Real>,
        s: Real,
    ) -> Result<(), SolverError> {
        let (n, ng) = (self.n, self.ng);
        if b.len() != 2 * n + ng {
            return Err(SolverError::DimensionMismatch {
                what: "BSQL right-hand side",
                expected: 2 * n + ng,
                got: b.len(),
            });
        }
        let (bv, rest) = b.split_at_mut(n);
        let (bl, bu) = rest.split_at_mut(ng);
        self.rhs[..n].copy_from_slice(bv);
        match cj {
            Some(c) => {
                // r_v − K r_u / cj
                self.k_rows.apply(bu, &mut self.rhs[..n], true, -1.0 / c);
                for k in 0..ng {
                    self.rhs[n + k] = s * bl[k] / c;
                }
                self.compliant_rhs(Some(c), s, bl, bu);
            }
            None => {
                for k in 0..ng {
                    self.rhs[n + k] = s * bl[k];
                }
                self.compliant_rhs(None, s, bl, bu);
            }
        }
        self.solve_saddle()?;
        match cj {
            Some(c) => {
                for i in 0..n {
                    bv[i] = self.rhs[i];
                    bu[i] = (bu[i] + bv[i]) / c;
                }
                for k in 0..ng {
                    bl[k] = s * self.rhs[n + k] / c;
                }
            }
            None => {
                bv.copy_from_slice(&self.rhs[..n]);
                for k in 0..ng {
                    bl[k] = s * self.rhs[n + k];
                }
                // δu' = r_u (the u-row of ∂F/∂y' is the identity).
            }
        }
        Ok(())
    }

    /// Solves the factorised saddle system in place in `rhs` (n + ng), through the Schur
    /// complement when the modal block is eliminated, and by component blocks when the last
    /// factorisation was theirs.
    fn solve_saddle(&mut self) -> Result<(), SolverError> {
        let n = self.n;
        let (lu, blocks) = (&mut self.lu, &mut self.blocks);
        let mut solve = |x: &mut [Real]| match blocks {
            Some(b) if self.blocks_factored => b.solve(x),
            _ => lu.solve(x),
        };
        match &mut self.modal {
            None => solve(&mut self.rhs),
            Some(blk) => {
                let nv = blk.kept.len();
                blk.forward(&self.rhs[..n], &mut self.red_rhs[..nv]);
                self.red_rhs[nv..].copy_from_slice(&self.rhs[n..]);
                solve(&mut self.red_rhs)?;
                blk.back(&self.red_rhs[..nv], &mut self.rhs[..n]);
                self.rhs[n..].copy_from_slice(&self.red_rhs[nv..]);
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory};
    use crate::bdf::DaeSystem;
    use crate::{Real, SolverError};
    use faer::Mat;

    /// Friction on DOF 0 with a speed dependence: F = (0.5 − 2 v₀) λ'₀.
    struct Falling;
    impl FrictionForces for Falling {
        fn add_forces(
            &mut self,
            _: Real,
            v: &[Real],
            l: &[Real],
            f: &mut [Real],
        ) -> Result<(), SolverError> {
            f[0] += (0.5 - 2.0 * v[0]) * l[0];
            Ok(())
        }
        fn add_tangents(
            &mut self,
            _: Real,
            v: &[Real],
            l: &[Real],
            d_dlam: &mut Mat<Real>,
            d_dv: Option<&mut Mat<Real>>,
        ) -> Result<(), SolverError> {
            d_dlam[(0, 0)] += 0.5 - 2.0 * v[0];
            if let Some(d) = d_dv {
                d[(0, 0)] += -2.0 * l[0];
            }
            Ok(())
        }
    }

    fn system(include: bool) -> BsqlSystem<Falling> {
        let m = Mat::from_fn(3, 3, |i, j| if i == j { 1.0 + i as Real } else { 0.1 });
        let k = Mat::from_fn(3, 3, |i, j| if i == j { 50.0 } else { -5.0 });
        let b = Mat::from_fn(3, 3, |i, j| 1e-3 * k[(i, j)]);
        let mut g = Mat::zeros(1, 3);
        g[(0, 1)] = 1.0;
        let opts = BsqlOptions {
            include_friction_damping: include,
            ..Default::default()
        };
        BsqlSystem::new(m, b, k, g, LoadHistory::default(), Falling, opts).unwrap()
    }

    /// After a Newton failure with a fresh matrix, the next iteration matrices carry C_f:
    /// their solves are those of the matrix with C_f always in.
    #[test]
    fn a_newton_failure_puts_the_friction_damping_into_later_matrices() {
        let y = [0.3, 0.0, -0.1, 0.0, 0.01, 0.02, 0.0];
        let yp = [0.0, 0.0, 0.0, 20.0, 0.3, 0.0, 0.1];
        let rhs = [1.0, -2.0, 0.5, 0.3, 0.2, -0.1, 0.4];
        let solve = |sys: &mut BsqlSystem<Falling>| {
            sys.setup_jacobian(0.0, &y, &yp, 50.0).unwrap();
            let mut b = rhs;
            sys.solve_jacobian(&mut b).unwrap();
            b
        };
        let (mut paper, mut with_cf) = (system(false), system(true));
        let before = solve(&mut paper);
        let want = solve(&mut with_cf);
        assert!((0..7).any(|i| (before[i] - want[i]).abs() > 1e-6));
        paper.newton_failed_with_fresh_matrix();
        let after = solve(&mut paper);
        assert_eq!(paper.stats().friction_damping_after_failure, 1);
        for i in 0..7 {
            assert!((after[i] - want[i]).abs() <= 1e-14 * (1.0 + want[i].abs()));
        }
        // Off with `friction_damping_near_stick = false`: the paper's matrix stays.
        let mut off = BsqlSystem::new(
            paper.M.clone(),
            paper.B.clone(),
            paper.K.clone(),
            paper.G.clone(),
            LoadHistory::default(),
            Falling,
            BsqlOptions {
                friction_damping_near_stick: false,
                ..Default::default()
            },
        )
        .unwrap();
        off.newton_failed_with_fresh_matrix();
        let kept = solve(&mut off);
        assert_eq!(off.stats().friction_damping_after_failure, 0);
        for i in 0..7 {
            assert!((kept[i] - before[i]).abs() <= 1e-14 * (1.0 + before[i].abs()));
        }
    }
}
