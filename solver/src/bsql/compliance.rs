//! Normal contact compliance: a penalty spring per constraint row in place of the rigid
//! constraint, in the transient, the steady state and the CEA.
//!
//! # Reference
//! The paper's contact is rigid: the row of gap k is $G_k v' = 0$ [Paper eq. (11)], the
//! twice-differentiated position constraint $G_k u = 0$ [Paper eq. (9)], and λ'_k, the
//! contact force, is whatever keeps it. A compliant gap carries a normal spring of stiffness
//! k_n per unit area (a penalty, e.g. psi/in) on its area A_k; its force follows the relative
//! normal displacement g_k = G_k u = (u_r − u_p)·n:
//! $$λ'_k = k_n A_k\, G_k u, \qquad p_{n,k} = −λ'_k/A_k + P_0 = P_0 − k_n\, G_k u,$$
//! so a pad pressed into the rotor (G_k u < 0) carries more pressure than the preload
//! [Paper eq. (1)], and the reference G u = 0 is the undeformed, preloaded contact of the
//! rigid model (its steady state also has G u = 0). λ stays the unknown (y = {v, λ, u}), so
//! the friction forces F_f(λ', v) of eqs. (4)–(7), the pressure of eq. (1), the tensile-gap
//! monitor and the separation events read λ' exactly as with rigid contact. The row is
//! written with the compliance c_k = 1/(k_n A_k):
//! $$F_{λ,k} = G_k u − c_k\, λ'_k = 0$$
//! (∂F/∂y' = −c_k on λ'_k: the system stays index 0 and the row tends to the position
//! constraint as c_k → 0). An open gap (separation) keeps its row λ'_k = λ'_{open,k} = P_0 A_k;
//! it opens where p_n = 0, i.e. G_k u = c_k λ'_{open,k}, and closes when G_k u returns there
//! (the force is continuous: no impact for a compliant row). With the smooth unilateral law of
//! [`super::smooth`] the row opens and closes through the law itself, with no event.
//!
//! # Derivation (iteration matrix)
//! With J = ∂F/∂y + c_j ∂F/∂y', the row reads $G_k δu − c_k c_j δλ_k = r_{λ,k}$; the u-row
//! gives δu = (r_u + δv)/c_j, and in the scaled unknown μ = c_j δλ/s of
//! [`super::jacobian`] (multiplying by s c_j)
//! $$s\,G_k δv − s^2 c_k c_j\, μ_k = s\,(c_j r_{λ,k} − G_k r_u).$$
//! For ∂F/∂y' alone (initial conditions): $−c_k δλ'_k = r_{λ,k}$, i.e. $−s^2 c_k μ_k = s\,r_{λ,k}$
//! with δλ' = s μ. In the steady state (K in place of A): $s G_k δu − s^2 c_k μ_k = s r_k$.
//! Each compliant row of J is multiplied by ρ_k = 1/(1 + s c_k c_j) (of ∂F/∂y' by
//! 1/(1 + s c_k)), which keeps its diagonal of the size of the A block for any c_j.
//!
//! # Energy
//! The contact springs are stored energy: $E_c = Σ_k ½ c_k λ'^2_k = Σ_k ½ k_n A_k (G_k u)^2$
//! (an open gap: the potential of its constant force, $λ'_{open,k} G_k u − ½ c_k λ'^2_{open,k}$,
//! continuous at the opening). Its rate is $Σ_k λ'_k G_k v$, the constraint power of these
//! rows, so [`super::BsqlSystem::observe`] adds E_c to the strain energy and leaves these rows
//! out of the constraint power; the balance of [`super::EnergyBalance`] then closes with
//! compliance as it does without.
//!
//! # CEA
//! Linearised, $N_k = δλ'_k = G_k u / c_k$: substituting in
//! $M ü + (B − C_f) u̇ + K u + (G^T − D) N = 0$ folds the compliant rows into the stiffness,
//! $$K_c = K + Σ_{k\ \rm compliant} (G^T − D)_{:,k}\, c_k^{-1}\, G_{k,:},$$
//! with the rigid rows left as constraints ([`compliant_cea`]). As c_k → 0 the roots tend to
//! the rigid ones (the error falls like c_k, i.e. 1/k_n).

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x >= 0.0)` deliberately rejects NaN too.

use faer::Mat;

use super::{BsqlSystem, FrictionForces};
use crate::cea::CeaMatrices;
use crate::{Real, SolverError};

/// Checks a compliance vector: every entry finite and ≥ 0 (0 = a rigid row).
pub(crate) fn check_compliance(c: &[Real], ng: usize) -> Result<(), SolverError> {
    if c.len() != ng {
        return Err(SolverError::DimensionMismatch {
            what: "contact compliance",
            expected: ng,
            got: c.len(),
        });
    }
    if let Some(k) = c.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
        return Err(SolverError::InvalidOption {
            field: "compliance",
            value: format!("{} (row {k})", c[k]),
            reason: "must be finite and >= 0 (1/(k_n A), 0 = rigid)",
        });
    }
    Ok(())
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BsqlSystem<F> {
    /// Sets the compliance c_k = 1/(k_n A_k) of each constraint row (length ng; 0 = the
    /// paper's rigid row G_k v' = 0). See the [module docs](self).
    pub fn set_compliance(&mut self, compliance: Vec<Real>) -> Result<(), SolverError> {
        check_compliance(&compliance, self.ng)?;
        self.factored = super::Factored::None;
        self.compliance = if compliance.iter().all(|&c| c == 0.0) {
            Vec::new()
        } else {
            compliance
        };
        Ok(())
    }

    /// The compliance per row (empty when every row is rigid).
    pub fn compliance(&self) -> &[Real] {
        &self.compliance
    }

    /// Compliance of row k (0 = rigid).
    #[inline]
    pub(crate) fn compliance_of(&self, k: usize) -> Real {
        self.compliance.get(k).copied().unwrap_or(0.0)
    }

    /// G_k x.
    #[inline]
    pub(crate) fn g_row_dot(&self, k: usize, x: &[Real]) -> Real {
        (0..self.n).map(|i| self.G[(k, i)] * x[i]).sum()
    }

    /// F_λ,k = G_k u − c_k λ'_k for the closed compliant rows (S_k(G_k u) − c_k λ'_k with the
    /// smooth unilateral law, [`super::smooth`]; the other rows are left as they are).
    pub(crate) fn compliant_residual(&self, u: &[Real], lamp: &[Real], rl: &mut [Real]) {
        for (k, &c) in self.compliance.iter().enumerate() {
            if c > 0.0 && !self.open[k] {
                let g = self.smooth_row(k, self.g_row_dot(k, u)).0;
                rl[k] = g - c * lamp[k]; // F_λ = G u − c λ'
            }
        }
    }

    /// Row scale ρ_k = 1/(1 + s c_k c_j) (c_j = 1 for ∂F/∂y'): it keeps the diagonal
    /// −s² c_k c_j ρ_k of the size of s (of the A block) however large c_j is (the first
    /// steps, the initial conditions), so the pivot test of the LU stays meaningful.
    fn compliant_row_scale(c: Real, cj: Option<Real>, s: Real) -> Real {
        1.0 / (1.0 + s * c * cj.unwrap_or(1.0))
    }

    /// The compliant rows of the scaled saddle matrix (after the rigid rows were written),
    /// each multiplied by ρ_k: the G part s G_k (J) or 0 (∂F/∂y'), the diagonal −s² c_k c_j
    /// (−s² c_k for ∂F/∂y'); `nv` is the size of the velocity block of the factorised matrix
    /// (n, or the kept DOFs when the modal block is eliminated).
    pub(crate) fn compliant_matrix_rows(&mut self, cj: Option<Real>, s: Real, nv: usize) {
        let n = nv;
        for k in 0..self.compliance.len() {
            let c = self.compliance[k];
            if !(c > 0.0) || self.open[k] {
                continue;
            }
            let rho = Self::compliant_row_scale(c, cj, s);
            // S_k' of the smooth unilateral law (1 for a linear row).
            let slope = self.smooth_slope_of(k);
            for i in 0..n {
                self.lu.a[(n + k, i)] = match cj {
                    Some(_) => rho * slope * self.lu.a[(n + k, i)],
                    None => 0.0,
                };
            }
            self.lu.a[(n + k, n + k)] = -rho * s * s * c * cj.unwrap_or(1.0);
        }
    }

    /// The compliant rows' right-hand side, ρ_k s (c_j r_λ,k − G_k r_u) for J and
    /// ρ_k s r_λ,k for ∂F/∂y' (r_λ and r_u as given to the solve).
    pub(crate) fn compliant_rhs(&mut self, cj: Option<Real>, s: Real, bl: &[Real], bu: &[Real]) {
        let n = self.n;
        for k in 0..self.compliance.len() {
            let c = self.compliance[k];
            if c > 0.0 && !self.open[k] {
                let rho = Self::compliant_row_scale(c, cj, s);
                self.rhs[n + k] = rho
                    * s
                    * match cj {
                        Some(cj) => cj * bl[k] - self.smooth_slope_of(k) * self.g_row_dot(k, bu),
                        None => bl[k],
                    };
            }
        }
    }

    /// Stored energy of the contact springs at (u, λ') (0 without compliance).
    pub(crate) fn contact_spring_energy(&self, u: &[Real], lamp: &[Real]) -> Real {
        let mut e = 0.0;
        for (k, &c) in self.compliance.iter().enumerate() {
            if c > 0.0 {
                e += if self.open[k] {
                    let l = self.lambda_dot_open[k];
                    l * self.g_row_dot(k, u) - 0.5 * c * l * l
                } else if self.smooth_width_of(k) > 0.0 {
                    self.smooth_row_energy(k, self.g_row_dot(k, u))
                } else {
                    0.5 * c * lamp[k] * lamp[k]
                };
            }
        }
        e
    }
}

/// The CEA matrices with the compliant rows folded into the stiffness: K_c = K + Σ_k
/// (Gᵀ − D)_{:,k} G_{k,:}/c_k over the rows with c_k > 0, G and D keeping the rigid rows
/// only (see the [module docs](self)).
///
/// # Errors
/// A compliance that is negative or not finite, or of the wrong length.
#[allow(non_snake_case)]
pub fn compliant_cea(sys: &CeaMatrices, compliance: &[Real]) -> Result<CeaMatrices, SolverError> {
    let Some(G) = sys.g.as_ref() else {
        return Ok(sys.clone());
    };
    let (ng, n) = (G.nrows(), G.ncols());
    check_compliance(compliance, ng)?;
    if compliance.iter().all(|&c| c == 0.0) {
        return Ok(sys.clone());
    }
    let mut k_c = sys.k.clone();
    for (k, &c) in compliance.iter().enumerate() {
        if c == 0.0 {
            continue;
        }
        let kn = 1.0 / c;
        for j in 0..n {
            let gkj = G[(k, j)];
            if gkj == 0.0 {
                continue;
            }
            for i in 0..n {
                let a = G[(k, i)] - sys.d.as_ref().map_or(0.0, |d| d[(i, k)]);
                k_c[(i, j)] += a * kn * gkj; // [Paper eq. (9)] with λ' = G u / c
            }
        }
    }
    let rigid: Vec<usize> = (0..ng).filter(|&k| compliance[k] == 0.0).collect();
    let (g, d) = if rigid.is_empty() {
        (None, None)
    } else {
        let g = Mat::from_fn(rigid.len(), n, |r, j| G[(rigid[r], j)]);
        let d = sys
            .d
            .as_ref()
            .map(|d| Mat::from_fn(n, rigid.len(), |i, r| d[(i, rigid[r])]));
        (Some(g), d)
    };
    Ok(CeaMatrices {
        m: sys.m.clone(),
        k: k_c,
        b: sys.b.clone(),
        g,
        d,
        c_f: sys.c_f.clone(),
    })
}
