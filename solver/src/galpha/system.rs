//! The BSQL equations in second-order form for the generalized-α integrator.
//!
//! Same inputs as [`crate::bsql::BsqlSystem::new`]: M, B, K (n × n), G (ng × n), the load
//! history P(t) and a [`FrictionForces`] model. The integrator's unknowns per step are the
//! accelerations q̈ = v' and the contact forces f = λ'.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use crate::bsql::check_matrices;
use crate::bsql::{FrictionForces, LoadHistory};
use crate::linalg::lu::DenseLu;
use crate::{Real, SolverError};

/// y ← β·y + α·A x (β = 0 for `Accum::Replace`, 1 for `Accum::Add`).
pub(crate) fn matvec(a: MatRef<'_, Real>, x: &[Real], y: &mut [Real], accum: Accum, alpha: Real) {
    let xr = MatRef::from_column_major_slice(x, x.len(), 1);
    let n = y.len();
    let yr = MatMut::from_column_major_slice_mut(y, n, 1);
    matmul(yr, accum, a, xr, alpha, Par::Seq);
}

/// M, B, K, G, P(t) and the friction model, with the saddle-matrix workspace.
#[allow(non_snake_case)]
pub struct GalphaSystem<F: FrictionForces> {
    pub(crate) M: Mat<Real>,
    pub(crate) B: Mat<Real>,
    pub(crate) K: Mat<Real>,
    pub(crate) G: Mat<Real>,
    pub(crate) load: LoadHistory,
    pub(crate) friction: F,
    pub(crate) n: usize,
    pub(crate) ng: usize,
    g_scale: Real,
    f_n: Vec<Real>,
    d_dlam: Mat<Real>,
    d_dv: Mat<Real>,
    rhs: Vec<Real>,
    lu: DenseLu,
    /// Scaling s of the multiplier block of the last factorisation (0: none).
    s: Real,
}

#[allow(non_snake_case)]
impl<F: FrictionForces> GalphaSystem<F> {
    /// Build from M, B, K (n × n), G (ng × n), the loads and the friction model.
    pub fn new(
        M: Mat<Real>,
        B: Mat<Real>,
        K: Mat<Real>,
        G: Mat<Real>,
        load: LoadHistory,
        friction: F,
    ) -> Result<Self, SolverError> {
        let (n, ng, g_scale) = check_matrices(&M, &B, &K, &G, &load)?;
        Ok(Self {
            M,
            B,
            K,
            G,
            load,
            friction,
            n,
            ng,
            g_scale: if g_scale > 0.0 { g_scale } else { 1.0 },
            f_n: vec![0.0; n],
            d_dlam: Mat::zeros(n, ng),
            d_dv: Mat::zeros(n, n),
            rhs: vec![0.0; n + ng],
            lu: DenseLu::new(n + ng),
            s: 0.0,
        })
    }

    /// Number of structural DOFs n.
    pub fn n_dof(&self) -> usize {
        self.n
    }

    /// Number of constraints ng.
    pub fn n_constraints(&self) -> usize {
        self.ng
    }

    /// Length of y = {v, λ, u}: 2n + ng.
    pub fn len(&self) -> usize {
        2 * self.n + self.ng
    }

    /// True for a system without DOFs.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The friction model.
    pub fn friction_mut(&mut self) -> &mut F {
        &mut self.friction
    }

    /// The load history.
    pub fn load(&self) -> &LoadHistory {
        &self.load
    }

    /// The constraint matrix G.
    pub fn g(&self) -> MatRef<'_, Real> {
        self.G.as_ref()
    }

    /// Split y (or y') into its partitions (v, λ, u).
    pub fn split<'a>(&self, y: &'a [Real]) -> (&'a [Real], &'a [Real], &'a [Real]) {
        let (v, rest) = y.split_at(self.n);
        let (l, u) = rest.split_at(self.ng);
        (v, l, u)
    }

    /// Residual of the equations of motion and of the constraint at (t, q̈, f, v, u):
    /// `res[..n]` = F_v, `res[n..]` = G q̈.
    ///
    /// # Reference
    /// $$F_v = M \ddot q + B v + K u + G^T f − P(t) − F_f(f, v),\qquad F_λ = G \ddot q$$
    /// [Paper eq. (16)] with v' = q̈, λ' = f (the u-row u' = v holds by construction).
    pub(crate) fn residual(
        &mut self,
        t: Real,
        qdd: &[Real],
        f: &[Real],
        v: &[Real],
        u: &[Real],
        res: &mut [Real],
    ) -> Result<(), SolverError> {
        let n = self.n;
        let (rv, rl) = res.split_at_mut(n);
        matvec(self.M.as_ref(), qdd, rv, Accum::Replace, 1.0); // [Paper eq. (16)]
        matvec(self.B.as_ref(), v, rv, Accum::Add, 1.0);
        matvec(self.K.as_ref(), u, rv, Accum::Add, 1.0);
        matvec(self.G.transpose(), f, rv, Accum::Add, 1.0);
        self.load.add_to(t, -1.0, rv);
        self.f_n.fill(0.0);
        self.friction.add_forces(t, v, f, &mut self.f_n)?;
        for (i, (r, ff)) in rv.iter_mut().zip(&self.f_n).enumerate() {
            if !ff.is_finite() {
                return Err(SolverError::NonFinite {
                    what: "friction force",
                    t,
                    index: i,
                    value: *ff,
                });
            }
            *r -= ff;
        }
        matvec(self.G.as_ref(), qdd, rl, Accum::Replace, 1.0); // [Paper eq. (11)]
        Ok(())
    }

    /// Form and factorise the Newton matrix for the unknowns (q̈, f).
    ///
    /// # Reference
    /// With v = v̂ + c_v q̈ and u = û + c_u q̈ (the Newmark updates, c_v = hγ c_a,
    /// c_u = h²β c_a), the derivative of (F_v, F_λ) is
    /// $$\begin{bmatrix} M + c_v (B − C_f) + c_u K & G^T − ∂F_f/∂λ' \\ G & 0 \end{bmatrix},$$
    /// eq. (18) of the paper divided by its α with α = 1/c_v (exactly so when c_u = c_v²,
    /// as for the trapezoidal rule) [Paper eq. (18)]. The multiplier block is scaled by
    /// s = max|A_ii|/max|G_ij| as in the BSQL system.
    pub(crate) fn factor(
        &mut self,
        t: Real,
        v: &[Real],
        f: &[Real],
        c_v: Real,
        c_u: Real,
        with_cf: bool,
    ) -> Result<(), SolverError> {
        let (n, ng) = (self.n, self.ng);
        self.s = 0.0;
        self.d_dlam.fill(0.0);
        let with_cf = with_cf && c_v > 0.0;
        if with_cf {
            self.d_dv.fill(0.0);
        }
        let d_dv = if with_cf { Some(&mut self.d_dv) } else { None };
        self.friction
            .add_tangents(t, v, f, &mut self.d_dlam, d_dv)?;
        let a = &mut self.lu.a;
        let mut a_scale: Real = 0.0;
        for j in 0..n {
            for i in 0..n {
                let mut x = self.M[(i, j)] + c_v * self.B[(i, j)] + c_u * self.K[(i, j)];
                if with_cf {
                    x -= c_v * self.d_dv[(i, j)];
                }
                a[(i, j)] = x; // [Paper eq. (18)]
            }
            a_scale = a_scale.max(a[(j, j)].abs());
        }
        let s = if a_scale > 0.0 {
            a_scale / self.g_scale
        } else {
            1.0
        };
        for k in 0..ng {
            for i in 0..n {
                a[(i, n + k)] = s * (self.G[(k, i)] - self.d_dlam[(i, k)]);
                a[(n + k, i)] = s * self.G[(k, i)];
            }
            for l in 0..ng {
                a[(n + k, n + l)] = 0.0;
            }
        }
        self.lu.factor("generalized-α iteration", t)?;
        self.s = s;
        Ok(())
    }

    /// Solve with the last factorisation: `b` = (r_v, r_λ) becomes (δq̈, δf).
    pub(crate) fn solve(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        let n = self.n;
        let s = self.s;
        if s == 0.0 {
            return Err(SolverError::Callback {
                t: Real::NAN,
                message: "generalized-α solve requested before a successful factorisation".into(),
            });
        }
        self.rhs[..n].copy_from_slice(&b[..n]);
        for k in 0..self.ng {
            self.rhs[n + k] = s * b[n + k];
        }
        self.lu.solve(&mut self.rhs)?;
        b[..n].copy_from_slice(&self.rhs[..n]);
        for k in 0..self.ng {
            b[n + k] = s * self.rhs[n + k];
        }
        Ok(())
    }

    /// ‖G v − g₀‖∞.
    pub(crate) fn drift(&self, v: &[Real], g0: &[Real]) -> Real {
        let mut m: Real = 0.0;
        for k in 0..self.ng {
            let mut gv = 0.0;
            for j in 0..self.n {
                gv += self.G[(k, j)] * v[j];
            }
            m = m.max((gv - g0[k]).abs());
        }
        m
    }
}
