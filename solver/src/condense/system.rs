//! The band-limited transient: the condensed model closed by the exact contact law, as a
//! semi-explicit index-1 DAE for the BDF.
//!
//! Unknowns y = [x; z]: the model's real states x (differential) and the contact outputs
//! z = [v_c; q] (algebraic): the velocities of the contact DOFs and the linear normal force of
//! every row (rigid: λ'⁰ + Ñ; compliant: G_k u/c_k). With the inputs f = [ramp(t) − ramp_ref;
//! r(z)] (the load change, then the remainder at the contact DOFs, see the
//! [module docs](super)):
//! ```text
//! F_x = x' − A_x x − B_x f = 0
//! F_z = z − z⁰ − C_z x − D_z f = 0
//! r(z) = F_f(λ'_true, v_c) − F_f⁰ − C_f⁰ v_c − D⁰ (q − λ'⁰) − Gᵀ (λ'_true − q)
//! ```
//! λ'_true = q for a bilateral row, min(q, λ'_open) for a unilateral compliant one (p_n =
//! P0 − λ'/A ≥ 0; its force is continuous, no event). ∂F/∂y' = diag(I, 0).
//!
//! # Derivation (iteration matrix)
//! J = ∂F/∂y + c_j ∂F/∂y' = [[c_j I − A_x, −B_r J_r], [−C_z, I − D_r J_r]] with J_r = ∂r/∂z,
//! B_r, D_r the contact inputs' columns: ∂r/∂v_c = C_f(v_c, λ'_true) − C_f⁰ and ∂r/∂q_k =
//! χ_k D_k − D⁰_k − G_kᵀ(χ_k − 1), χ_k = ∂λ'_true/∂q_k ∈ {0, 1}. J_r vanishes at the reference
//! (the remainder's derivative is zero there), so the *linear* matrix J_r = 0 — block lower
//! triangular, solved with the 2×2 blocks of c_j I − A_x and one product with C_z, no
//! factorisation — serves while the response is small; after a Newton failure with a fresh
//! matrix, or when the friction reports a contact near sticking, the full matrix is formed
//! and factorised (dense LU of n_states + n_z).

use super::BandModel;
use crate::bdf::{DaeSystem, TolerancePartition, Tolerances};
use crate::bsql::{FrictionForces, LoadHistory};
use crate::linalg::lu::DenseLu;
use crate::{Real, SolverError};
use faer::linalg::solvers::Solve;
use faer::Mat;
use serde::{Deserialize, Serialize};

/// The contact rows of the band-limited transient.
#[derive(Debug, Clone)]
pub struct BandContact {
    /// G, every row (ng × n): rigid rows are the model's multipliers (in order), compliant rows
    /// springs.
    pub g: Mat<Real>,
    /// Compliance c_k = 1/(k_n A_k) per row (0: rigid).
    pub compliance: Vec<Real>,
    /// λ'_open of a unilateral compliant row (None: bilateral).
    pub open_force: Vec<Option<Real>>,
}

/// The state the model was linearised about.
#[derive(Debug, Clone)]
pub struct BandReference {
    /// Displacements u⁰ (length n).
    pub u: Vec<Real>,
    /// Contact forces λ'⁰ (length ng).
    pub lambda_dot: Vec<Real>,
    /// The load factor ramp_ref there (1: the whole brake load).
    pub ramp: Real,
}

/// Counters of the band-limited system.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BandSystemStats {
    /// Residual evaluations.
    pub residual_evals: u64,
    /// Set-ups of the linear (block-triangular) iteration matrix.
    pub linear_setups: u64,
    /// Factorisations of the full iteration matrix.
    pub full_factorisations: u64,
    /// Newton iterations of the steady states and initial values.
    pub algebraic_iterations: u64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Matrix {
    None,
    Linear(Real),
    Full,
}

/// The band-limited model as a [`DaeSystem`].
#[allow(non_snake_case)]
pub struct BandSystem<F: FrictionForces> {
    model: BandModel,
    friction: F,
    load: LoadHistory,
    reference: BandReference,
    contact: BandContact,
    /// Contact DOFs (the model's inputs).
    dofs: Vec<usize>,
    /// Row of the model's multipliers of each rigid row.
    rigid_of: Vec<Option<usize>>,
    /// F_f⁰, C_f⁰, D⁰ at the contact DOFs.
    f0: Vec<Real>,
    cf0: Mat<Real>,
    d0: Mat<Real>,
    /// G at the contact DOFs (ng × n_c).
    g_c: Mat<Real>,
    /// z⁰, C_z, D_z.
    z0: Vec<Real>,
    C_z: Mat<Real>,
    D_z: Mat<Real>,
    /// R⁺ = Rᵀ(RRᵀ)⁻¹ (n_c × n_v): contact velocities of the velocity outputs.
    r_pinv: Mat<Real>,
    /// P⁺ = (PᵀP)⁻¹Pᵀ (n_p × n_c): pattern coefficients of a remainder at the contact DOFs.
    p_pinv: Mat<Real>,
    /// The remainder at the contact DOFs (n_c).
    r_c: Vec<Real>,
    n_x: usize,
    /// Contact DOFs.
    n_c: usize,
    /// Velocity outputs n_v.
    n_v: usize,
    /// Force patterns n_p.
    n_p: usize,
    ng: usize,
    /// First contact input.
    o: usize,
    // Workspace.
    v_full: Vec<Real>,
    f_full: Vec<Real>,
    f_in: Vec<Real>,
    lam: Vec<Real>,
    d_full: Mat<Real>,
    cf_full: Mat<Real>,
    lu: DenseLu,
    matrix: Matrix,
    full_always: bool,
    /// The unilateral rows open (q > λ'_open) where the iteration matrix was formed, and at
    /// the last residual's point: the matrix is stale when they differ
    /// ([`DaeSystem::matrix_stale`]).
    open_at_setup: Vec<bool>,
    open_now: Vec<bool>,
    /// Scale s of the friction force, s F_f (default 1: the friction law as given); the
    /// continuation parameter of the limit cycles (μ → s μ for a law proportional to μ).
    scale: Real,
    stats: BandSystemStats,
}

fn dim(what: &'static str, expected: usize, got: usize) -> Result<(), SolverError> {
    if expected != got {
        return Err(SolverError::DimensionMismatch {
            what,
            expected,
            got,
        });
    }
    Ok(())
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BandSystem<F> {
    /// The system of `model` (its rigid rows the rows of `contact` with compliance 0, in order)
    /// with the friction law, the loads (whose `p_brake` is the model's load input) and the
    /// reference state.
    ///
    /// # Errors
    /// Sizes that disagree; a unilateral rigid row; a friction force or tangent at a DOF that is
    /// not a contact DOF of the model.
    pub fn new(
        model: BandModel,
        mut friction: F,
        load: LoadHistory,
        reference: BandReference,
        contact: BandContact,
    ) -> Result<Self, SolverError> {
        let n = model.n;
        let ng = contact.g.nrows();
        dim("band contact G (columns)", n, contact.g.ncols())?;
        dim("band contact compliance", ng, contact.compliance.len())?;
        dim("band contact open forces", ng, contact.open_force.len())?;
        dim("band reference u", n, reference.u.len())?;
        dim("band reference λ'", ng, reference.lambda_dot.len())?;
        load.validate(n)?;
        let has_load = !model.inputs.load.is_empty();
        if has_load == load.p_brake.is_empty() {
            return Err(SolverError::InvalidOption {
                field: "band model load input",
                value: format!(
                    "model {has_load}, load history {}",
                    !load.p_brake.is_empty()
                ),
                reason: "the model needs a load input exactly when the loads have a brake load",
            });
        }
        let mut rigid_of = vec![None; ng];
        let mut r = 0;
        for k in 0..ng {
            if contact.compliance[k] == 0.0 {
                if contact.open_force[k].is_some() {
                    return Err(SolverError::InvalidOption {
                        field: "band contact open force",
                        value: format!("row {k}"),
                        reason: "a unilateral row of the band-limited model must be compliant",
                    });
                }
                rigid_of[k] = Some(r);
                r += 1;
            }
        }
        dim("band model rigid rows", model.ng, r)?;
        let dofs = model.inputs.contact_dofs.clone();
        let n_c = dofs.len();
        let mut is_contact = vec![false; n];
        for &d in &dofs {
            is_contact[d] = true;
        }
        // The friction at the reference, and where it acts.
        let zero = vec![0.0; n];
        let mut f_full = vec![0.0; n];
        friction.add_forces(-1.0, &zero, &reference.lambda_dot, &mut f_full)?;
        let mut d_full = Mat::zeros(n, ng);
        let mut cf_full = Mat::zeros(n, n);
        friction.add_tangents(
            -1.0,
            &zero,
            &reference.lambda_dot,
            &mut d_full,
            Some(&mut cf_full),
        )?;
        for i in 0..n {
            let touched = f_full[i] != 0.0
                || (0..ng).any(|k| d_full[(i, k)] != 0.0 || contact.g[(k, i)] != 0.0)
                || (0..n).any(|j| cf_full[(i, j)] != 0.0 || cf_full[(j, i)] != 0.0);
            if touched && !is_contact[i] {
                return Err(SolverError::InvalidOption {
                    field: "band model contact DOFs",
                    value: format!("DOF {i}"),
                    reason: "the contact rows or the friction act on a DOF that is not an input",
                });
            }
        }
        let f0: Vec<Real> = dofs.iter().map(|&d| f_full[d]).collect();
        let cf0 = Mat::from_fn(n_c, n_c, |a, b| cf_full[(dofs[a], dofs[b])]);
        let d0 = Mat::from_fn(n_c, ng, |a, k| d_full[(dofs[a], k)]);
        let g_c = Mat::from_fn(ng, n_c, |k, a| contact.g[(k, dofs[a])]);
        // Patterns and velocity rows, and their pseudo-inverses.
        let pm = model.inputs.pattern_matrix();
        let rm = model.inputs.velocity_matrix();
        let (n_p, n_v) = (pm.ncols(), rm.nrows());
        let p_pinv = pseudo_inverse(&pm.transpose().to_owned(), "band model force patterns")?
            .transpose()
            .to_owned();
        let r_pinv = pseudo_inverse(&rm, "band model velocity rows")?;
        // The contact law must act through the patterns and read the velocity rows only: the
        // friction tangents and the rows at the reference, projected.
        let mut probe = Mat::zeros(n_c, n_c + ng);
        for a in 0..n_c {
            for b in 0..n_c {
                probe[(a, b)] = cf0[(a, b)];
            }
            for k in 0..ng {
                // A unilateral row's normal pair enters the remainder when it opens.
                let open = if contact.open_force[k].is_some() {
                    1.0
                } else {
                    0.0
                };
                probe[(a, n_c + k)] = d0[(a, k)] + open * g_c[(k, a)];
            }
        }
        let off_span = &probe - &pm * (&p_pinv * &probe);
        let unread = &cf0 - &(&cf0 * &r_pinv) * &rm;
        let scale = probe.norm_max().max(Real::MIN_POSITIVE);
        if off_span.norm_max() > 1e-8 * scale || unread.norm_max() > 1e-8 * scale {
            return Err(SolverError::InvalidOption {
                field: "band model patterns / velocity rows",
                value: format!(
                    "{:e} outside the patterns, {:e} unread by the rows (of {:e})",
                    off_span.norm_max(),
                    unread.norm_max(),
                    scale
                ),
                reason: "the friction tangents and contact rows must lie in the patterns' span \
                         and read the velocities through the rows",
            });
        }
        // The outputs z = [w; q].
        let n_x = model.n_states;
        let n_in = model.inputs.len();
        let n_z = n_v + ng;
        let mut C_z = Mat::zeros(n_z, n_x);
        let mut D_z = Mat::zeros(n_z, n_in);
        let mut z0 = vec![0.0; n_z];
        let cv_c = Mat::from_fn(n_c, n_x, |a, j| model.C_v[(dofs[a], j)]);
        let dv_c = Mat::from_fn(n_c, n_in, |a, j| model.D_v[(dofs[a], j)]);
        C_z.submatrix_mut(0, 0, n_v, n_x).copy_from(&rm * &cv_c);
        D_z.submatrix_mut(0, 0, n_v, n_in).copy_from(&rm * &dv_c);
        for k in 0..ng {
            let row = n_v + k;
            match rigid_of[k] {
                Some(r) => {
                    z0[row] = reference.lambda_dot[k];
                    for j in 0..n_x {
                        C_z[(row, j)] = model.C_N[(r, j)];
                    }
                    for j in 0..n_in {
                        D_z[(row, j)] = model.D_N[(r, j)];
                    }
                }
                None => {
                    let kn = 1.0 / contact.compliance[k];
                    z0[row] = kn
                        * (0..n)
                            .map(|i| contact.g[(k, i)] * reference.u[i])
                            .sum::<Real>();
                    for (a, &d) in dofs.iter().enumerate() {
                        let gk = kn * g_c[(k, a)];
                        if gk == 0.0 {
                            continue;
                        }
                        for j in 0..n_x {
                            C_z[(row, j)] += gk * model.C_u[(d, j)];
                        }
                        for j in 0..n_in {
                            D_z[(row, j)] += gk * model.D_u[(d, j)];
                        }
                    }
                }
            }
        }
        let o = model.inputs.first_contact();
        Ok(Self {
            model,
            friction,
            load,
            reference,
            contact,
            dofs,
            rigid_of,
            f0,
            cf0,
            d0,
            g_c,
            z0,
            C_z,
            D_z,
            r_pinv,
            p_pinv,
            r_c: vec![0.0; n_c],
            n_x,
            n_c,
            n_v,
            n_p,
            ng,
            o,
            v_full: vec![0.0; n],
            f_full,
            f_in: vec![0.0; n_in],
            lam: vec![0.0; ng],
            d_full,
            cf_full,
            lu: DenseLu::new(n_x + n_z),
            matrix: Matrix::None,
            full_always: false,
            open_at_setup: vec![false; ng],
            open_now: vec![false; ng],
            scale: 1.0,
            stats: BandSystemStats::default(),
        })
    }

    /// The condensed model.
    pub fn model(&self) -> &BandModel {
        &self.model
    }

    /// Counters.
    pub fn stats(&self) -> &BandSystemStats {
        &self.stats
    }

    /// Scales the friction force by `s` (μ → s μ for a law proportional to μ; default 1). The
    /// linear part stays the one linearised at s = 1: the remainder carries the difference
    /// exactly, (s − 1) F_f included.
    pub fn set_friction_scale(&mut self, s: Real) {
        self.scale = s;
        self.matrix = Matrix::None;
    }

    /// The friction scale (see [`BandSystem::set_friction_scale`]).
    pub fn friction_scale(&self) -> Real {
        self.scale
    }

    /// Number of real states n_x (the differential unknowns come first in y).
    pub fn n_states(&self) -> usize {
        self.n_x
    }

    /// Form and factorise the full iteration matrix at every set-up (default: only after a
    /// Newton failure with a fresh linear matrix, or near sticking).
    pub fn set_full_matrix(&mut self, on: bool) {
        self.full_always = on;
        self.matrix = Matrix::None;
    }

    /// Tolerances: (rtol1, atol1) on the states and the contact velocities, (rtol2, atol2) on
    /// the normal forces (atol2 ≥ 1e20 leaves them out, as BSQL's multipliers).
    pub fn tolerances(&self, rtol1: Real, atol1: Real, rtol2: Real, atol2: Real) -> Tolerances {
        let p = |len, rtol, atol| TolerancePartition { len, rtol, atol };
        Tolerances::Partitions {
            parts: vec![
                p(self.n_x + self.n_v, rtol1, atol1),
                p(self.ng, rtol2, atol2),
            ],
        }
    }

    /// The contact force λ'_true of every row from the linear normal forces q.
    fn true_forces(&mut self, q: &[Real]) {
        for k in 0..self.ng {
            self.lam[k] = match self.contact.open_force[k] {
                Some(open) => q[k].min(open),
                None => q[k],
            };
        }
    }

    /// The inputs f = [ramp(t) − ramp_ref; P⁺ r(z)] into `self.f_in` (the remainder at the
    /// contact DOFs in `self.r_c`).
    fn inputs(&mut self, t: Real, z: &[Real]) -> Result<(), SolverError> {
        let (w, q) = z.split_at(self.n_v);
        self.true_forces(q);
        self.v_full.fill(0.0);
        let n_c = self.n_c;
        // Dense products by faer's kernels (the matrices are n_c × n_c and n_c × ng: on the
        // cad brake's 2 043-DOF model 1 920 contact DOFs and 550 rows).
        let v_c = mat_vec(&self.r_pinv, w);
        for (a, &d) in self.dofs.iter().enumerate() {
            self.v_full[d] = v_c[a];
        }
        self.f_full.fill(0.0);
        self.friction
            .add_forces(t, &self.v_full, &self.lam, &mut self.f_full)?;
        if self.o == 1 {
            self.f_in[0] = self.load.ramp(t) - self.reference.ramp;
        }
        let (ng, o) = (self.ng, self.o);
        let dq: Vec<Real> = (0..ng)
            .map(|k| q[k] - self.reference.lambda_dot[k])
            .collect();
        let dl: Vec<Real> = (0..ng).map(|k| self.lam[k] - q[k]).collect();
        let cf_v = mat_vec(&self.cf0, &v_c);
        let d_q = mat_vec(&self.d0, &dq);
        let g_l = self.g_c.transpose() * faer::ColRef::from_slice(&dl);
        for a in 0..n_c {
            let r = self.scale * self.f_full[self.dofs[a]] - self.f0[a] - cf_v[a] - d_q[a] - g_l[a];
            if !r.is_finite() {
                return Err(SolverError::NonFinite {
                    what: "band-limited remainder",
                    t,
                    index: self.dofs[a],
                    value: r,
                });
            }
            self.r_c[a] = r;
        }
        let coef = mat_vec(&self.p_pinv, &self.r_c);
        self.f_in[o..o + self.n_p].copy_from_slice(&coef);
        Ok(())
    }

    /// F_z = z − z⁰ − C_z x − D_z f into `out` (inputs already in `self.f_in`).
    fn output_residual(&self, x: &[Real], z: &[Real], out: &mut [Real]) {
        let cx = mat_vec(&self.C_z, &x[..self.n_x]);
        let df = mat_vec(&self.D_z, &self.f_in);
        for (i, o) in out.iter_mut().enumerate() {
            *o = z[i] - self.z0[i] - cx[i] - df[i];
        }
    }

    /// A_x x + B_x f into `out`.
    fn state_rate(&self, x: &[Real], out: &mut [Real]) {
        let bf = mat_vec(&self.model.B_x, &self.f_in);
        out.copy_from_slice(&bf);
        self.model.add_linear(x, out);
    }

    /// J_r = ∂(P⁺ r)/∂z (n_p × n_z) at (t, z) (after `inputs`).
    fn remainder_jacobian(&mut self, t: Real, z: &[Real]) -> Result<Mat<Real>, SolverError> {
        let (n_c, ng, n_v) = (self.n_c, self.ng, self.n_v);
        self.d_full.fill(0.0);
        self.cf_full.fill(0.0);
        self.friction.add_tangents(
            t,
            &self.v_full,
            &self.lam,
            &mut self.d_full,
            Some(&mut self.cf_full),
        )?;
        let q = &z[n_v..];
        // ∂r/∂v_c (n_c × n_c) and ∂r/∂q (n_c × ng) at the contact DOFs.
        let dv = Mat::from_fn(n_c, n_c, |a, b| {
            self.scale * self.cf_full[(self.dofs[a], self.dofs[b])] - self.cf0[(a, b)]
        });
        let dq = Mat::from_fn(n_c, ng, |a, k| {
            let chi = if is_open(&self.contact, q, k) {
                0.0
            } else {
                1.0
            };
            chi * self.scale * self.d_full[(self.dofs[a], k)]
                - self.d0[(a, k)]
                - self.g_c[(k, a)] * (chi - 1.0)
        });
        let mut jr = Mat::zeros(self.n_p, n_v + ng);
        jr.submatrix_mut(0, 0, self.n_p, n_v)
            .copy_from(&self.p_pinv * (&dv * &self.r_pinv));
        jr.submatrix_mut(0, n_v, self.n_p, ng)
            .copy_from(&self.p_pinv * &dq);
        Ok(jr)
    }

    /// Solves z = c + H f(t, z) for z by Newton (∂/∂z = I − H_r J_r, H_r the contact inputs'
    /// columns of H), from the z given.
    fn solve_affine(
        &mut self,
        t: Real,
        c: &[Real],
        h: &Mat<Real>,
        z: &mut [Real],
    ) -> Result<(), SolverError> {
        let n_z = z.len();
        let n_in = self.f_in.len();
        let mut res = vec![0.0; n_z];
        let mut lu = DenseLu::new(n_z);
        let max_iters = 50;
        for it in 0..=max_iters {
            self.inputs(t, z)?;
            for i in 0..n_z {
                res[i] = z[i] - c[i] - (0..n_in).map(|j| h[(i, j)] * self.f_in[j]).sum::<Real>();
            }
            let scale = z.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            let rn = res.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if rn <= 1e-12 * scale {
                return Ok(());
            }
            if it == max_iters {
                return Err(SolverError::NewtonFailed {
                    what: "band-limited contact outputs",
                    iterations: it,
                    residual: rn,
                    tolerance: 1e-12 * scale,
                });
            }
            let jr = self.remainder_jacobian(t, z)?;
            let hr = h.subcols(self.o, self.n_p) * &jr;
            for j in 0..n_z {
                for i in 0..n_z {
                    lu.a[(i, j)] = if i == j { 1.0 } else { 0.0 } - hr[(i, j)];
                }
            }
            lu.factor("band-limited outputs", t)?;
            lu.solve(&mut res)?;
            for i in 0..n_z {
                z[i] -= res[i];
            }
            self.stats.algebraic_iterations += 1;
        }
        Ok(())
    }

    /// x ← A_x⁻¹ x (the 2×2 blocks of the kept pairs, the real roots).
    fn apply_a_inverse(&self, x: &mut [Real]) {
        for (p, &o) in self.model.roots.iter().zip(&self.model.offsets) {
            if p.im != 0.0 {
                // [[σ, −ω], [ω, σ]]⁻¹ = [[σ, ω], [−ω, σ]] / |λ|².
                let (a, b) = (x[o], x[o + 1]);
                let d = p.norm_sqr();
                x[o] = (p.re * a + p.im * b) / d;
                x[o + 1] = (-p.im * a + p.re * b) / d;
            } else {
                x[o] /= p.re;
            }
        }
    }

    /// The steady state at time `t_steady` (x' = 0: x = −A_x⁻¹ B_x f, z = z⁰ + H_z(0) f with
    /// the static map H_z(0) = D_z − C_z A_x⁻¹ B_x, solved for z by Newton), then the initial
    /// values at `t0`: y0 = [x; z(t0)], y0' = [A_x x + B_x f(t0); 0] (z solved again at t0 with
    /// x fixed: a step load changes the static response at once).
    ///
    /// # Errors
    /// A callback failure or a Newton that does not converge.
    pub fn initial_values(
        &mut self,
        t_steady: Real,
        t0: Real,
    ) -> Result<(Vec<Real>, Vec<Real>), SolverError> {
        let (n_x, n_z) = (self.n_x, self.n_v + self.ng);
        let n_in = self.f_in.len();
        let mut ainv_b = self.model.B_x.clone();
        for j in 0..n_in {
            let mut col: Vec<Real> = (0..n_x).map(|i| ainv_b[(i, j)]).collect();
            self.apply_a_inverse(&mut col);
            for i in 0..n_x {
                ainv_b[(i, j)] = col[i];
            }
        }
        let h0 = &self.D_z - &self.C_z * &ainv_b;
        let mut z = self.z0.clone();
        let z0 = self.z0.clone();
        self.solve_affine(t_steady, &z0, &h0, &mut z)?;
        self.inputs(t_steady, &z)?;
        let x: Vec<Real> = (0..n_x)
            .map(|i| {
                -(0..n_in)
                    .map(|j| ainv_b[(i, j)] * self.f_in[j])
                    .sum::<Real>()
            })
            .collect();
        // At t0 with x fixed.
        let c: Vec<Real> = (0..n_z)
            .map(|i| self.z0[i] + (0..n_x).map(|j| self.C_z[(i, j)] * x[j]).sum::<Real>())
            .collect();
        let dz = self.D_z.clone();
        self.solve_affine(t0, &c, &dz, &mut z)?;
        let mut rate = vec![0.0; n_x];
        self.inputs(t0, &z)?;
        self.state_rate(&x, &mut rate);
        let mut y = x;
        y.extend_from_slice(&z);
        let mut yp = rate;
        yp.resize(n_x + n_z, 0.0);
        Ok((y, yp))
    }

    /// The full model's variables at (t, y, y'): u, v (length n each) and the contact forces
    /// λ' (length ng), for records and monitors; v' ≈ C_v x' (the static correction's rate left
    /// out) into `vp` when given.
    ///
    /// # Errors
    /// A friction callback failure.
    pub fn physical(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        u: &mut [Real],
        v: &mut [Real],
        lambda_dot: &mut [Real],
        vp: Option<&mut [Real]>,
    ) -> Result<(), SolverError> {
        let (x, z) = y.split_at(self.n_x);
        self.inputs(t, z)?;
        let n = self.model.n;
        let (cu, cv) = (mat_vec(&self.model.C_u, x), mat_vec(&self.model.C_v, x));
        let (du, dv) = (
            mat_vec(&self.model.D_u, &self.f_in),
            mat_vec(&self.model.D_v, &self.f_in),
        );
        for i in 0..n {
            u[i] = self.reference.u[i] + cu[i] + du[i];
            v[i] = cv[i] + dv[i];
        }
        lambda_dot.copy_from_slice(&self.lam);
        if let Some(vp) = vp {
            vp.copy_from_slice(&mat_vec(&self.model.C_v, &yp[..self.n_x]));
        }
        Ok(())
    }

    /// Solves the linear (block-triangular) iteration matrix in place.
    fn solve_linear(&self, cj: Real, b: &mut [Real]) {
        let (bx, bz) = b.split_at_mut(self.n_x);
        for (p, &o) in self.model.roots.iter().zip(&self.model.offsets) {
            if p.im != 0.0 {
                // [[cj − σ, ω], [−ω, cj − σ]] [a; b] = rhs.
                let (d, w) = (cj - p.re, p.im);
                let det = d * d + w * w;
                let (r0, r1) = (bx[o], bx[o + 1]);
                bx[o] = (d * r0 - w * r1) / det;
                bx[o + 1] = (w * r0 + d * r1) / det;
            } else {
                bx[o] /= cj - p.re;
            }
        }
        for (i, z) in bz.iter_mut().enumerate() {
            *z += (0..self.n_x)
                .map(|j| self.C_z[(i, j)] * bx[j])
                .sum::<Real>();
        }
    }
}

impl<F: FrictionForces> DaeSystem for BandSystem<F> {
    fn len(&self) -> usize {
        self.n_x + self.n_v + self.ng
    }

    fn residual(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        res: &mut [Real],
    ) -> Result<(), SolverError> {
        self.stats.residual_evals += 1;
        let (x, z) = y.split_at(self.n_x);
        self.inputs(t, z)?;
        open_rows(&self.contact, &z[self.n_v..], &mut self.open_now);
        let (rx, rz) = res.split_at_mut(self.n_x);
        self.state_rate(x, rx);
        for (r, p) in rx.iter_mut().zip(yp) {
            *r = p - *r;
        }
        self.output_residual(x, z, rz);
        Ok(())
    }

    fn setup_jacobian(
        &mut self,
        t: Real,
        y: &[Real],
        _yp: &[Real],
        cj: Real,
    ) -> Result<(), SolverError> {
        let (x, z) = y.split_at(self.n_x);
        let _ = x;
        self.inputs(t, z)?;
        open_rows(&self.contact, &z[self.n_v..], &mut self.open_at_setup);
        let any_open = self.open_at_setup.iter().any(|&o| o);
        let near = self.friction.near_stick(t, &self.v_full, &self.lam);
        // The linear matrix (J_r = 0) is the reference's, every row closed: an open row's
        // ∂r/∂q (Gᵀ − D⁰) is not small, and a matrix without it can diverge.
        if !(self.full_always || near || any_open) {
            self.matrix = Matrix::Linear(cj);
            self.stats.linear_setups += 1;
            return Ok(());
        }
        self.matrix = Matrix::None;
        let jr = self.remainder_jacobian(t, z)?;
        let n_x = self.n_x;
        let n_z = self.n_v + self.ng;
        let bj = self.model.B_x.subcols(self.o, self.n_p) * &jr;
        let dj = self.D_z.subcols(self.o, self.n_p) * &jr;
        let a = &mut self.lu.a;
        a.fill(0.0);
        for i in 0..n_x {
            for j in 0..n_z {
                a[(i, n_x + j)] = -bj[(i, j)];
            }
        }
        for (p, &o) in self.model.roots.iter().zip(&self.model.offsets) {
            if p.im != 0.0 {
                a[(o, o)] = cj - p.re;
                a[(o, o + 1)] = p.im;
                a[(o + 1, o)] = -p.im;
                a[(o + 1, o + 1)] = cj - p.re;
            } else {
                a[(o, o)] = cj - p.re;
            }
        }
        for i in 0..n_z {
            for j in 0..n_x {
                a[(n_x + i, j)] = -self.C_z[(i, j)];
            }
            for j in 0..n_z {
                a[(n_x + i, n_x + j)] = if i == j { 1.0 } else { 0.0 } - dj[(i, j)];
            }
        }
        self.lu.factor("band-limited iteration", t)?;
        self.stats.full_factorisations += 1;
        self.matrix = Matrix::Full;
        Ok(())
    }

    fn solve_jacobian(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        match self.matrix {
            Matrix::Linear(cj) => {
                self.solve_linear(cj, b);
                Ok(())
            }
            Matrix::Full => self.lu.solve(b),
            Matrix::None => Err(SolverError::Callback {
                t: Real::NAN,
                message: "band-limited solve requested before a set-up".into(),
            }),
        }
    }

    fn newton_failed_with_fresh_matrix(&mut self) {
        self.full_always = true;
    }

    /// A unilateral row opened or closed since the matrix was formed (χ_k of J_r changed).
    fn matrix_stale(&self) -> bool {
        self.open_now != self.open_at_setup
    }
}

impl<F: FrictionForces> BandSystem<F> {
    /// The rigid row of the model's multipliers for each contact row (None: compliant).
    pub fn rigid_rows(&self) -> &[Option<usize>] {
        &self.rigid_of
    }

    /// Number of velocity outputs n_v (the first n_v outputs z are the velocity rows' values,
    /// the next ng the rows' normal forces).
    pub fn n_velocities(&self) -> usize {
        self.n_v
    }

    /// Number of force patterns n_p (the inputs after the load).
    pub fn n_patterns(&self) -> usize {
        self.n_p
    }

    /// Number of contact rows ng.
    pub fn n_rows(&self) -> usize {
        self.ng
    }

    /// The contact DOFs.
    pub fn contact_dofs(&self) -> &[usize] {
        &self.dofs
    }

    /// The reference outputs z⁰ (zero velocities, the reference normal forces).
    pub fn z_reference(&self) -> &[Real] {
        &self.z0
    }

    /// C_z (n_z × n_x) and D_z (n_z × inputs): z = z⁰ + C_z x + D_z f.
    #[allow(non_snake_case)]
    pub fn output_maps(&self) -> (&Mat<Real>, &Mat<Real>) {
        (&self.C_z, &self.D_z)
    }

    /// The inputs f(t, z) (length inputs: the load change, then the remainder's pattern
    /// coefficients) and, when `jacobian`, J_r = ∂f_patterns/∂z (n_p × n_z).
    ///
    /// # Errors
    /// A friction callback failure or a non-finite remainder.
    pub fn evaluate(
        &mut self,
        t: Real,
        z: &[Real],
        jacobian: bool,
    ) -> Result<(&[Real], Option<Mat<Real>>), SolverError> {
        self.inputs(t, z)?;
        let jr = if jacobian {
            Some(self.remainder_jacobian(t, z)?)
        } else {
            None
        };
        Ok((&self.f_in, jr))
    }

    /// The contact rows (G, compliance, open forces).
    pub fn contact(&self) -> &BandContact {
        &self.contact
    }

    /// The contact forces λ'_true of the outputs z (after [`BandSystem::evaluate`] at z).
    pub fn contact_forces(&self) -> &[Real] {
        &self.lam
    }
}

/// Row k is unilateral and open: q_k > λ'_open (χ_k = 0 in J_r).
fn is_open(contact: &BandContact, q: &[Real], k: usize) -> bool {
    contact.open_force[k].is_some_and(|open| q[k] > open)
}

/// Which unilateral rows are open at the linear normal forces q, into `out`.
fn open_rows(contact: &BandContact, q: &[Real], out: &mut [bool]) {
    for (k, o) in out.iter_mut().enumerate() {
        *o = is_open(contact, q, k);
    }
}

/// `a x` by faer's dense kernel.
fn mat_vec(a: &Mat<Real>, x: &[Real]) -> Vec<Real> {
    let y = a * faer::ColRef::from_slice(x);
    y.iter().copied().collect()
}

/// A⁺ = Aᵀ(AAᵀ)⁻¹ of a full-row-rank A (rows × cols).
fn pseudo_inverse(a: &Mat<Real>, what: &'static str) -> Result<Mat<Real>, SolverError> {
    let gram = a * a.transpose();
    let llt = gram
        .llt(faer::Side::Lower)
        .map_err(|_| SolverError::InvalidOption {
            field: what,
            value: format!("{} x {}", a.nrows(), a.ncols()),
            reason: "must have full row rank",
        })?;
    let mut x = a.clone();
    llt.solve_in_place(&mut x);
    Ok(x.transpose().to_owned())
}
