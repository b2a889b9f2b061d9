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
//! # Where a low-rank update would go
//! Only D = ∂F_f/∂λ' (and C_f) change between factorisations at equal cj, and they are
//! non-zero only in the rows of the contact DOFs. Factorising S₀ (the matrix with D = 0)
//! once per cj and applying the Woodbury identity with the rank-(#contact rows) correction
//! in [`BsqlSystem::assemble_iteration_matrix`]/`solve_iteration` would replace the O((n+ng)³)
//! refactorisation by O((n+ng)²·r) work; with cj changing every few steps the gain also needs
//! a cj-independent splitting (e.g. modal coordinates), which is future work.

use faer::Mat;

use super::{BsqlSystem, FrictionForces};
use crate::{Real, SolverError};

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
        let v = &y[..n];
        let lamp = &yp[n..n + ng];
        // Friction tangents at the current point.
        self.d_dlam.fill(0.0);
        let near_stick = cj.is_some()
            && !self.opts.include_friction_damping
            && self.opts.friction_damping_near_stick
            && self.friction.near_stick(t, v, lamp);
        let with_cf = (self.opts.include_friction_damping || near_stick) && cj.is_some();
        if near_stick {
            self.stats.near_stick_factorisations += 1;
        }
        if with_cf {
            self.d_dv.fill(0.0);
        }
        self.stats.tangent_evals += 1;
        let d_dv = if with_cf { Some(&mut self.d_dv) } else { None };
        self.friction
            .add_tangents(t, v, lamp, &mut self.d_dlam, d_dv)?;
        let a = &mut self.lu.a;
        // A block, column by column on contiguous slices (vectorised).
        let a_scale = crate::linalg::sparse::dispatch(FillA {
            a,
            m: &self.M,
            b: &self.B,
            k: &self.K,
            cf: with_cf.then_some(&self.d_dv),
            cj,
            n,
        });
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
        for k in 0..ng {
            for i in 0..n {
                a[(i, n + k)] = s * (self.G[(k, i)] - self.d_dlam[(i, k)]);
                a[(n + k, i)] = if self.open[k] {
                    0.0
                } else {
                    s * self.G[(k, i)]
                };
            }
            for l in 0..ng {
                a[(n + k, n + l)] = 0.0;
            }
            if self.open[k] {
                a[(n + k, n + k)] = d_open;
            }
        }
        self.compliant_matrix_rows(cj, s);
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
                self.k_rows.apply(0, bu, &mut self.rhs[..n], true, -1.0 / c);
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
        self.lu.solve(&mut self.rhs)?;
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
}
