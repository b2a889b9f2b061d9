//! The static sliding equilibrium (initial state of the transient and base state of CEA).

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.

use faer::{Accum, Mat};
use serde::{Deserialize, Serialize};

use super::residual::{matvec, LoadHistory};
use super::{BsqlSystem, FrictionForces};
use crate::{Real, SolverError};

/// Options of the steady-state Newton solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SteadyOptions {
    /// Tolerance on the residual ∞-norm relative to max(1, ‖P(t)‖∞) (default: 1e-10).
    pub tol: Real,
    /// Maximum Newton iterations (default: 50).
    pub max_iters: usize,
}

impl Default for SteadyOptions {
    fn default() -> Self {
        Self {
            tol: 1e-10,
            max_iters: 50,
        }
    }
}

impl SteadyOptions {
    /// Check ranges; the error names the field.
    pub fn validate(&self) -> Result<(), SolverError> {
        if !(self.tol > 0.0 && self.tol.is_finite()) {
            return Err(SolverError::InvalidOption {
                field: "tol",
                value: self.tol.to_string(),
                reason: "must be finite and > 0",
            });
        }
        if self.max_iters == 0 {
            return Err(SolverError::InvalidOption {
                field: "max_iters",
                value: "0".into(),
                reason: "must be >= 1",
            });
        }
        Ok(())
    }
}

/// A steady sliding state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyState {
    /// Time at which the loads were evaluated.
    pub t: Real,
    /// Displacements u (length n).
    pub u: Vec<Real>,
    /// Contact forces λ' (length ng).
    pub lambda_dot: Vec<Real>,
    /// Newton iterations used.
    pub iterations: usize,
    /// Final residual ∞-norm.
    pub residual_norm: Real,
}

impl SteadyState {
    /// Consistent initial values for the transient: y = {v = 0, λ = 0, u}, y' = {0, λ', 0}.
    pub fn initial_values(&self) -> (Vec<Real>, Vec<Real>) {
        let (n, ng) = (self.u.len(), self.lambda_dot.len());
        let mut y = vec![0.0; 2 * n + ng];
        y[n + ng..].copy_from_slice(&self.u);
        let mut yp = vec![0.0; 2 * n + ng];
        yp[n..n + ng].copy_from_slice(&self.lambda_dot);
        (y, yp)
    }
}

/// Solve the static sliding equilibrium at time t (loads P(t)) by Newton's method.
///
/// # Reference
/// Eq. (8) with v = v' = 0, Q from [Paper eq. (12)] and the position form of the constraint
/// [Paper eq. (9)]:
/// $$K u + G^T λ' = P(t) + F_f(λ', 0),\qquad G u = 0,$$
/// (a compliant row k: $G_k u − c_k λ'_k = 0$, see [`super::compliance`]; the Newton matrix
/// then has −c_k on its diagonal),
/// Newton matrix $\begin{bmatrix} K & G^T − ∂F_f/∂λ' \\ G & 0\end{bmatrix}$ (the v-, λ-
/// columns of eq. (18) at α = 0 with K in place of αM + B), scaled as in the transient.
#[allow(non_snake_case)]
pub fn steady_state<F: FrictionForces>(
    sys: &mut BsqlSystem<F>,
    t: Real,
    opts: &SteadyOptions,
) -> Result<SteadyState, SolverError> {
    let mut factorisations = 0;
    let statics = Statics {
        k: &sys.K,
        g: &sys.G,
        load: &sys.load,
        friction: &mut sys.friction,
        compliance: &sys.compliance,
    };
    let r = solve(statics, sys.g_scale, t, opts, &mut factorisations);
    sys.stats.factorisations += factorisations;
    r
}

/// What the steady state reads of a problem: K, G, the loads, the friction forces and the
/// compliant rows (empty: every row rigid).
pub struct Statics<'a, F> {
    pub k: &'a Mat<Real>,
    pub g: &'a Mat<Real>,
    pub load: &'a LoadHistory,
    pub friction: &'a mut F,
    pub compliance: &'a [Real],
}

/// [`steady_state`] from the matrices themselves, without the transient's [`BsqlSystem`]
/// (whose set-up — sparse row patterns of M, B, K, the modal elimination, the component
/// blocks — the static solve never uses): a CEA per sample builds only what it needs.
/// Checks the sizes, the loads and the compliance as [`BsqlSystem::new`] does.
///
/// # Errors
/// As [`steady_state`]; sizes that do not match (named), a bad load or compliance.
pub fn steady_state_of<F: FrictionForces>(
    statics: Statics<'_, F>,
    t: Real,
    opts: &SteadyOptions,
) -> Result<SteadyState, SolverError> {
    let n = statics.k.nrows();
    let (_, ng, g_scale) = super::check_statics(n, statics.k, statics.g, statics.load)?;
    if !statics.compliance.is_empty() {
        super::compliance::check_compliance(statics.compliance, ng)?;
    }
    let g_scale = if g_scale > 0.0 { g_scale } else { 1.0 };
    solve(statics, g_scale, t, opts, &mut 0)
}

/// The Newton solve of [`steady_state`]; counts its factorisations in `factorisations`.
fn solve<F: FrictionForces>(
    sys: Statics<'_, F>,
    g_scale: Real,
    t: Real,
    opts: &SteadyOptions,
    factorisations: &mut u64,
) -> Result<SteadyState, SolverError> {
    opts.validate()?;
    let (n, ng) = (sys.k.nrows(), sys.g.nrows());
    let mut u = vec![0.0; n];
    let mut lamp = vec![0.0; ng];
    let zero_v = vec![0.0; n];
    let mut r = vec![0.0; n + ng];
    let mut p = vec![0.0; n];
    // The whole (n + ng) Newton matrix (the system's own LU may be the reduced one of the
    // modal elimination); allocated once per call.
    let mut lu = crate::linalg::lu::DenseLu::new(n + ng);
    let mut f_n = vec![0.0; n];
    let mut d_dlam = Mat::<Real>::zeros(n, ng);
    sys.load.add_to(t, 1.0, &mut p);
    let scale = p.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let tol = opts.tol * scale;
    let mut iterations = 0;
    loop {
        // Residual.
        let (ru, rg) = r.split_at_mut(n);
        matvec(sys.k.as_ref(), &u, ru, Accum::Replace, 1.0);
        matvec(sys.g.transpose(), &lamp, ru, Accum::Add, 1.0);
        f_n.fill(0.0);
        sys.friction.add_forces(t, &zero_v, &lamp, &mut f_n)?;
        for i in 0..n {
            ru[i] -= p[i] + f_n[i];
        }
        matvec(sys.g.as_ref(), &u, rg, Accum::Replace, 1.0);
        for (k, &c) in sys.compliance.iter().enumerate() {
            rg[k] -= c * lamp[k]; // a compliant row: G u − c λ' = 0
        }
        let mut rn: Real = 0.0;
        for (i, x) in r.iter().enumerate() {
            if !x.is_finite() {
                return Err(SolverError::NonFinite {
                    what: "steady-state residual",
                    t,
                    index: i,
                    value: *x,
                });
            }
            rn = rn.max(x.abs());
        }
        if rn <= tol {
            return Ok(SteadyState {
                t,
                u,
                lambda_dot: lamp,
                iterations,
                residual_norm: rn,
            });
        }
        if iterations == opts.max_iters {
            return Err(SolverError::NewtonFailed {
                what: "steady state",
                iterations,
                residual: rn,
                tolerance: tol,
            });
        }
        iterations += 1;
        // Newton matrix.
        d_dlam.fill(0.0);
        sys.friction
            .add_tangents(t, &zero_v, &lamp, &mut d_dlam, None)?;
        let a = &mut lu.a;
        let mut k_scale: Real = 0.0;
        for j in 0..n {
            for i in 0..n {
                a[(i, j)] = sys.k[(i, j)];
            }
            k_scale = k_scale.max(sys.k[(j, j)].abs());
        }
        let s = if k_scale > 0.0 {
            k_scale / g_scale
        } else {
            1.0
        };
        for k in 0..ng {
            for i in 0..n {
                a[(i, n + k)] = s * (sys.g[(k, i)] - d_dlam[(i, k)]);
                a[(n + k, i)] = s * sys.g[(k, i)];
            }
            for l in 0..ng {
                a[(n + k, n + l)] = 0.0;
            }
            a[(n + k, n + k)] = -s * s * sys.compliance.get(k).copied().unwrap_or(0.0);
        }
        lu.factor("steady-state Newton", t)?;
        *factorisations += 1;
        for k in 0..ng {
            r[n + k] *= s;
        }
        lu.solve(&mut r)?;
        for i in 0..n {
            u[i] -= r[i];
        }
        for k in 0..ng {
            lamp[k] -= s * r[n + k];
        }
    }
}
