//! Generalized-α integrator for the BSQL equations: an independent cross-check of the BDF.
//!
//! The method is Chung & Hulbert's generalized-α (J. Appl. Mech. 60 (1993) 371–375) in the
//! form of Arnold & Brüls for constrained systems (Multibody Syst. Dyn. 18 (2007) 185–202):
//! the equations of motion hold exactly at every step point,
//! $$M \ddot q_{n+1} + B v_{n+1} + K u_{n+1} + G^T f_{n+1} − P(t_{n+1}) − F_f(f_{n+1}, v_{n+1}) = 0,
//! \qquad G \ddot q_{n+1} = 0,$$
//! and a pseudo-acceleration a carries the α-averaging into Newmark's updates:
//! $$(1−α_m) a_{n+1} + α_m a_n = (1−α_f)\ddot q_{n+1} + α_f \ddot q_n,$$
//! $$u_{n+1} = u_n + h v_n + h^2\big((\tfrac12 − β) a_n + β a_{n+1}\big),\quad
//! v_{n+1} = v_n + h\big((1−γ) a_n + γ a_{n+1}\big).$$
//!
//! # The constraint
//! As in the BDF formulation ([Paper eq. (11)], G v' = 0), the contact constraint is imposed at
//! the acceleration level, G q̈_{n+1} = 0, with the contact force f = λ' as its multiplier.
//! With a₀ = q̈₀ (so G a₀ = 0) the a-recursion gives G a_n = 0 for all n, hence
//! G v_{n+1} = G v_n: G v stays at its initial value up to the Newton residual (the monitor
//! is [`GalphaStats::max_constraint_drift`]). Since G q̈ = 0 fixes f through the saddle
//! matrix, no index-3 treatment (Arnold–Brüls' position-level constraint) is needed.
//! The impulse λ (y's middle partition) does not enter the equations; it is accumulated with
//! the trapezoidal rule λ_{n+1} = λ_n + h/2 (f_n + f_{n+1}).
//!
//! # Output
//! The callback and the accessors use the BDF's layout: y = {v, λ, u},
//! y' = {q̈, f = λ', v}, and F(t, y, y') = 0 of [Paper eq. (16)] holds at every step point.
//! Output between steps is cubic Hermite.
//!
//! - [`options`]: options, coefficients from ρ∞, statistics.
//! - [`system`]: the matrices and the friction model ([`GalphaSystem`]).
//! - [`initial`]: consistent initial accelerations and contact forces.
//! - [`step`]: one step: Newton on (q̈, f), the local error estimate, step-size control.
//! - [`spectral`]: amplification matrix and algorithmic damping (the theory the tests check).

pub mod initial;

pub mod options;
pub mod spectral;
pub mod step;
pub mod system;

pub use options::{GalphaCoeffs, GalphaOptions, GalphaStats};
pub use spectral::{
    algorithmic_damping, amplification_matrix, principal_root, spectral_radius, AlgorithmicDamping,
};
pub use system::GalphaSystem;

use crate::bsql::FrictionForces;
use crate::{Real, SolverError};

/// How a `step_to` call ended: the BDF's [`Status`](crate::bdf::Status), with `order` = 2 (the
/// method's order of accuracy) in the failure variants, so callers can swap integrators.
pub use crate::bdf::Status;

/// Solution at one step point: everything the next step and the output need.
#[derive(Debug, Clone)]
pub(crate) struct Point {
    pub t: Real,
    pub u: Vec<Real>,
    pub v: Vec<Real>,
    /// Pseudo-acceleration a.
    pub a: Vec<Real>,
    /// Acceleration q̈ = v'.
    pub qdd: Vec<Real>,
    /// Contact force f = λ'.
    pub f: Vec<Real>,
    /// Contact impulse λ.
    pub lam: Vec<Real>,
}

impl Point {
    fn zeros(n: usize, ng: usize) -> Self {
        Self {
            t: 0.0,
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
            qdd: vec![0.0; n],
            f: vec![0.0; ng],
            lam: vec![0.0; ng],
        }
    }

    fn copy_from(&mut self, o: &Point) {
        self.t = o.t;
        self.u.copy_from_slice(&o.u);
        self.v.copy_from_slice(&o.v);
        self.a.copy_from_slice(&o.a);
        self.qdd.copy_from_slice(&o.qdd);
        self.f.copy_from_slice(&o.f);
        self.lam.copy_from_slice(&o.lam);
    }

    /// y = {v, λ, u}, y' = {q̈, f, v}.
    fn write_y(&self, y: &mut [Real], yp: &mut [Real]) {
        let (n, ng) = (self.v.len(), self.f.len());
        y[..n].copy_from_slice(&self.v);
        y[n..n + ng].copy_from_slice(&self.lam);
        y[n + ng..].copy_from_slice(&self.u);
        yp[..n].copy_from_slice(&self.qdd);
        yp[n..n + ng].copy_from_slice(&self.f);
        yp[n + ng..].copy_from_slice(&self.v);
    }
}

/// Scratch vectors, allocated once.
#[derive(Debug, Clone)]
pub(crate) struct Work {
    /// Residual / Newton correction, length n + ng.
    pub delta: Vec<Real>,
    /// Error weights on y = {v, λ, u}.
    pub ewt: Vec<Real>,
    pub rtol: Vec<Real>,
    pub atol: Vec<Real>,
    /// Parts of u_{n+1}, v_{n+1}, a_{n+1} that do not depend on q̈_{n+1}.
    pub u_base: Vec<Real>,
    pub v_base: Vec<Real>,
    pub a_base: Vec<Real>,
    /// G v₀.
    pub g0: Vec<Real>,
    /// y, y' at the last step point or output time.
    pub y_out: Vec<Real>,
    pub yp_out: Vec<Real>,
    /// ‖F‖∞ at the last residual evaluation.
    pub last_res_norm: Real,
}

/// The generalized-α integrator: options, state and workspace.
#[derive(Debug, Clone)]
pub struct Galpha {
    pub(crate) opts: GalphaOptions,
    pub(crate) co: GalphaCoeffs,
    /// Current step point t_n.
    pub(crate) cur: Point,
    /// Previous step point t_{n−1} (valid when `has_prev`).
    pub(crate) prev: Point,
    /// Trial solution at t_{n+1}.
    pub(crate) trial: Point,
    pub(crate) has_prev: bool,
    /// Step size for the next step.
    pub(crate) h: Real,
    /// Step size whose shift δh the current pseudo-acceleration corresponds to.
    pub(crate) a_h: Real,
    /// Fixed steps: start time and whole steps since (t = t_base + k h); adaptive: steps
    /// accepted at the current h.
    pub(crate) t_base: Real,
    pub(crate) k_base: u64,
    /// Fixed steps: halvings of h for the substeps of the current step (0: no substeps).
    pub(crate) halvings: u32,
    /// Step size at which the iteration matrix was factorised (None: not factorised).
    pub(crate) factored_h: Option<Real>,
    /// Newton rate estimate ρ/(1 − ρ).
    pub(crate) ss: Real,
    pub(crate) stats: GalphaStats,
    pub(crate) w: Work,
}

impl Galpha {
    /// New integrator at (t0, y0) with y = {v, λ, u}; y0' = {q̈, λ', v} is only a starting
    /// guess: the accelerations and contact forces are solved for so that
    /// F(t0, y0, y0') = 0 (see [`initial`]). v₀ and u₀ are kept.
    pub fn new<F: FrictionForces>(
        opts: GalphaOptions,
        sys: &mut GalphaSystem<F>,
        t0: Real,
        y0: &[Real],
        yp0: &[Real],
    ) -> Result<Self, SolverError> {
        opts.validate()?;
        let started = std::time::Instant::now();
        let (n, ng) = (sys.n, sys.ng);
        let len = 2 * n + ng;
        for (what, l) in [("y0", y0.len()), ("y0'", yp0.len())] {
            if l != len {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: len,
                    got: l,
                });
            }
        }
        if !t0.is_finite() {
            return Err(SolverError::InvalidOption {
                field: "t0",
                value: t0.to_string(),
                reason: "must be finite",
            });
        }
        let v = || vec![0.0; len];
        let mut w = Work {
            delta: vec![0.0; n + ng],
            ewt: v(),
            rtol: v(),
            atol: v(),
            u_base: vec![0.0; n],
            v_base: vec![0.0; n],
            a_base: vec![0.0; n],
            g0: vec![0.0; ng],
            y_out: v(),
            yp_out: v(),
            last_res_norm: 0.0,
        };
        opts.tolerances.expand(len, &mut w.rtol, &mut w.atol)?;
        let mut cur = Point::zeros(n, ng);
        cur.t = t0;
        cur.v.copy_from_slice(&y0[..n]);
        cur.lam.copy_from_slice(&y0[n..n + ng]);
        cur.u.copy_from_slice(&y0[n + ng..]);
        cur.qdd.copy_from_slice(&yp0[..n]);
        cur.f.copy_from_slice(&yp0[n..n + ng]);
        let mut me = Self {
            co: GalphaCoeffs::from_rho_inf(opts.rho_inf),
            h: opts.h,
            a_h: opts.h,
            opts,
            prev: cur.clone(),
            trial: cur.clone(),
            cur,
            has_prev: false,
            t_base: t0,
            k_base: 0,
            halvings: 0,
            factored_h: None,
            ss: 20.0,
            stats: GalphaStats::default(),
            w,
        };
        me.initial_solve(sys)?;
        me.cur.a.copy_from_slice(&me.cur.qdd);
        for k in 0..ng {
            let mut gv = 0.0;
            for j in 0..n {
                gv += sys.G[(k, j)] * me.cur.v[j];
            }
            me.w.g0[k] = gv;
        }
        me.cur.write_y(&mut me.w.y_out, &mut me.w.yp_out);
        me.stats.cpu_s += started.elapsed().as_secs_f64();
        Ok(me)
    }

    /// The options in use.
    pub fn options(&self) -> &GalphaOptions {
        &self.opts
    }

    /// The method coefficients in use.
    pub fn coeffs(&self) -> &GalphaCoeffs {
        &self.co
    }

    /// Counters so far.
    pub fn stats(&self) -> &GalphaStats {
        &self.stats
    }

    /// Time of the last step point.
    pub fn t(&self) -> Real {
        self.cur.t
    }

    /// Step size of the next step.
    pub fn h(&self) -> Real {
        self.h
    }

    /// y = {v, λ, u} at the last output time (or at t0 after `new`).
    pub fn y(&self) -> &[Real] {
        &self.w.y_out
    }

    /// y' = {q̈, λ', v} at the last output time (or at t0 after `new`).
    pub fn yp(&self) -> &[Real] {
        &self.w.yp_out
    }

    /// Integrate to `tout` (step past it and interpolate, like the BDF), calling
    /// `on_step(system, t_n, y_n, y'_n)` after every accepted step; it returns `Ok(false)` to stop.
    pub fn step_to<F, C>(
        &mut self,
        sys: &mut GalphaSystem<F>,
        tout: Real,
        mut on_step: C,
    ) -> Result<Status, SolverError>
    where
        F: FrictionForces,
        C: FnMut(&mut GalphaSystem<F>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        let started = std::time::Instant::now();
        let out = self.step_to_inner(sys, tout, &mut on_step);
        self.stats.cpu_s += started.elapsed().as_secs_f64();
        out
    }

    /// Integrate to `tout` without a per-step callback.
    pub fn integrate_to<F: FrictionForces>(
        &mut self,
        sys: &mut GalphaSystem<F>,
        tout: Real,
    ) -> Result<Status, SolverError> {
        self.step_to(sys, tout, |_, _, _, _| Ok(true))
    }

    fn step_to_inner<F, C>(
        &mut self,
        sys: &mut GalphaSystem<F>,
        tout: Real,
        on_step: &mut C,
    ) -> Result<Status, SolverError>
    where
        F: FrictionForces,
        C: FnMut(&mut GalphaSystem<F>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        if sys.len() != self.w.y_out.len() {
            return Err(SolverError::DimensionMismatch {
                what: "system length vs integrator state",
                expected: self.w.y_out.len(),
                got: sys.len(),
            });
        }
        let t_min = if self.has_prev {
            self.prev.t
        } else {
            self.cur.t
        };
        if !tout.is_finite() || tout < t_min {
            return Err(SolverError::BadOutputTime {
                tout,
                t_min,
                t_max: Real::INFINITY,
            });
        }
        // Times within this distance of a step point count as reached (round-off of t).
        let eps = |h: Real, t: Real| 1e-9 * h + 4.0 * Real::EPSILON * t.abs();
        let mut steps = 0usize;
        loop {
            if self.cur.t >= tout - eps(self.h, tout) {
                self.output_at(tout);
                return Ok(Status::Reached { t: tout });
            }
            if steps >= self.opts.max_steps {
                self.cur.write_y(&mut self.w.y_out, &mut self.w.yp_out);
                return Ok(Status::MaxSteps {
                    t: self.cur.t,
                    steps,
                });
            }
            if let Some(status) = self.step(sys)? {
                self.cur.write_y(&mut self.w.y_out, &mut self.w.yp_out);
                return Ok(status);
            }
            steps += 1;
            self.cur.write_y(&mut self.w.y_out, &mut self.w.yp_out);
            if !on_step(sys, self.cur.t, &self.w.y_out, &self.w.yp_out)? {
                return Ok(Status::Interrupted { t: self.cur.t });
            }
        }
    }

    /// y, y' at `tout` ∈ [t_{n−1}, t_n]: the step point itself when within round-off,
    /// otherwise cubic Hermite interpolation of (u, v), (v, q̈) and (λ, f).
    fn output_at(&mut self, tout: Real) {
        let (p, c) = (&self.prev, &self.cur);
        let h = c.t - p.t;
        if !self.has_prev || (tout - c.t).abs() <= 1e-9 * h.abs() {
            c.write_y(&mut self.w.y_out, &mut self.w.yp_out);
            return;
        }
        let th = (tout - p.t) / h;
        let (n, ng) = (c.v.len(), c.f.len());
        let (y, yp) = (&mut self.w.y_out, &mut self.w.yp_out);
        for i in 0..n {
            let (vv, dv) = hermite(th, h, p.v[i], p.qdd[i], c.v[i], c.qdd[i]);
            let (uu, du) = hermite(th, h, p.u[i], p.v[i], c.u[i], c.v[i]);
            y[i] = vv;
            yp[i] = dv;
            y[n + ng + i] = uu;
            yp[n + ng + i] = du;
        }
        for k in 0..ng {
            let (l, dl) = hermite(th, h, p.lam[k], p.f[k], c.lam[k], c.f[k]);
            y[n + k] = l;
            yp[n + k] = dl;
        }
    }
}

/// Cubic Hermite interpolant through (y0, y0') at θ = 0 and (y1, y1') at θ = 1 on a step of
/// size h: returns the value and the time derivative at θ.
fn hermite(th: Real, h: Real, y0: Real, d0: Real, y1: Real, d1: Real) -> (Real, Real) {
    let t2 = th * th;
    let t3 = t2 * th;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + th;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    let y = h00 * y0 + h10 * h * d0 + h01 * y1 + h11 * h * d1;
    let dh00 = (6.0 * t2 - 6.0 * th) / h;
    let dh10 = 3.0 * t2 - 4.0 * th + 1.0;
    let dh01 = (-6.0 * t2 + 6.0 * th) / h;
    let dh11 = 3.0 * t2 - 2.0 * th;
    (y, dh00 * y0 + dh10 * d0 + dh01 * y1 + dh11 * d1)
}

#[cfg(test)]
mod tests {
    use super::hermite;

    #[test]
    fn hermite_reproduces_cubics() {
        // y = 1 + 2t − t² + 0.5 t³ on [0.3, 0.8].
        let y = |t: f64| 1.0 + 2.0 * t - t * t + 0.5 * t * t * t;
        let d = |t: f64| 2.0 - 2.0 * t + 1.5 * t * t;
        let (a, b) = (0.3, 0.8);
        for th in [0.0, 0.25, 0.6, 1.0] {
            let t = a + th * (b - a);
            let (v, dv) = hermite(th, b - a, y(a), d(a), y(b), d(b));
            assert!((v - y(t)).abs() < 1e-14 && (dv - d(t)).abs() < 1e-13);
        }
    }
}
