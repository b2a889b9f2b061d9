//! DASSL/IDA-style BDF integrator for implicit systems F(t, y, y') = 0.
//!
//! Fixed-leading-coefficient, variable-step BDF of orders 1..=`max_order` in modified
//! divided-difference (φ) form, following the published IDA algorithm (Hindmarsh et al.,
//! SUNDIALS IDA; Brenan, Campbell & Petzold for DASSL), re-derived and written from scratch:
//!
//! - [`coeffs`]: step coefficients α, β, σ, γ, ψ, the leading coefficient cj, predictor.
//! - [`newton`]: the corrector — modified Newton on F(t_n, y, y'(y)) with the iteration
//!   matrix J = ∂F/∂y + cj ∂F/∂y' [Paper eq. (17)], reused while cj/cj_old ∈ [0.6, 1/0.6].
//! - [`error_test`]: error weights, weighted RMS norms, the local error test and order
//!   lowering, and failure recovery.
//! - [`step`]: one step and its completion (step-size and order selection).
//! - [`interpolate`]: the interpolating polynomial for output between steps.
//! - [`initial`]: consistent initial derivatives.
//! - [`roots`]: restart at an event ([`Bdf::reinit`]) and root location on the interpolant.
//! - [`warm`]: restart at order 2 from a Taylor start ([`Bdf::reinit_taylor`]) and y'' of the
//!   DAE ([`warm::second_derivative`]).
//! - [`state`]: the serialisable state for restarts, and the statistics.

pub mod coeffs;
pub mod error_test;
pub mod initial;
pub mod interpolate;
pub mod newton;
pub mod options;
pub mod roots;
pub mod state;
pub mod step;
mod validate;
pub mod warm;

use serde::Serialize;

pub use initial::{consistent_initial_conditions, IcStats};
pub use options::{
    BdfOptions, InitialConditionOptions, TolerancePartition, Tolerances, ATOL_EXCLUDED,
};
pub use state::{BdfState, BdfStats, JacobianPoint};

use crate::{Real, SolverError};

/// An implicit system F(t, y, y') = 0 with a user-managed iteration matrix.
pub trait DaeSystem {
    /// Number of components of y.
    fn len(&self) -> usize;
    /// True for an empty system.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Evaluate F(t, y, y') into `res`.
    fn residual(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        res: &mut [Real],
    ) -> Result<(), SolverError>;
    /// Form and factorise J = ∂F/∂y + cj ∂F/∂y' at (t, y, y').
    fn setup_jacobian(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        cj: Real,
    ) -> Result<(), SolverError>;
    /// Solve J x = b in place with the last factorisation.
    fn solve_jacobian(&mut self, b: &mut [Real]) -> Result<(), SolverError>;
    /// Optionally form and factorise ∂F/∂y' alone (the limit cj → ∞ of J/cj), used by the
    /// consistent-initial-condition solve; afterwards `solve_jacobian` must solve with it.
    /// Return `Ok(false)` (the default) if not provided: the solve then uses a large cj.
    fn setup_derivative_jacobian(
        &mut self,
        _t: Real,
        _y: &[Real],
        _yp: &[Real],
    ) -> Result<bool, SolverError> {
        Ok(false)
    }
    /// Told when Newton failed to converge with a matrix formed for this very attempt (the
    /// step is then retried with a smaller one): a system whose matrix leaves terms out may
    /// put them in from now on (default: nothing).
    fn newton_failed_with_fresh_matrix(&mut self) {}
    /// Asked when a Newton attempt is about to fail (too slow a rate or the iteration limit),
    /// after a residual evaluation at its iterate: true when that point lies on another branch
    /// of a piecewise law than the iteration matrix was formed on (a unilateral contact that
    /// opened or closed). The matrix is then formed again there and the attempt goes on, a
    /// semi-smooth Newton: a matrix of the wrong branch can make the iteration diverge at
    /// every step size (default: never).
    fn matrix_stale(&self) -> bool {
        false
    }
}

/// How a `step_to` call ended. Failures to converge are statuses, not errors.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Status {
    /// The output time was reached; `Bdf::y()`/`Bdf::yp()` hold the solution there.
    Reached {
        /// The output time.
        t: Real,
    },
    /// The step size fell below `h_min` (or the round-off floor) after failures.
    StepSizeTooSmall {
        /// Internal time of the failed step's start.
        t: Real,
        /// Step size that was too small.
        h: Real,
        /// Order of the failed step.
        order: usize,
        /// ‖F‖∞ at the last residual evaluation (NaN if it was not finite).
        residual_norm: Real,
    },
    /// Too many error-test failures on one step.
    ErrorTestFailures {
        /// Internal time of the failed step's start.
        t: Real,
        /// Last step size tried.
        h: Real,
        /// Order of the failed step.
        order: usize,
        /// Weighted local error estimate (≤ 1 passes).
        error_norm: Real,
    },
    /// Too many Newton convergence failures on one step (or one in a fixed-step run).
    ConvergenceFailures {
        /// Internal time of the failed step's start.
        t: Real,
        /// Last step size tried.
        h: Real,
        /// Order of the failed step.
        order: usize,
        /// ‖F‖∞ at the last residual evaluation (NaN if it was not finite).
        residual_norm: Real,
    },
    /// `max_steps` steps were taken in this call before reaching the output time.
    MaxSteps {
        /// Internal time reached.
        t: Real,
        /// Steps taken in this call.
        steps: usize,
    },
    /// The per-step callback asked to stop; `y()`/`yp()` hold the last step's solution.
    Interrupted {
        /// Time of the last accepted step.
        t: Real,
    },
    /// `collapse_steps` consecutive accepted steps were shorter than `h_collapse`
    /// ([`BdfOptions::h_collapse`]); `y()`/`yp()` hold the last step's solution.
    StepCollapse {
        /// Time of the last accepted step.
        t: Real,
        /// Its step size.
        h: Real,
        /// Its order.
        order: usize,
        /// The threshold the steps stayed below.
        h_collapse: Real,
        /// Consecutive accepted steps below it.
        steps: u64,
    },
}

impl Status {
    /// True for `Reached`.
    pub fn is_success(&self) -> bool {
        matches!(self, Status::Reached { .. })
    }
}

/// Scratch vectors, allocated once.
#[derive(Debug, Clone)]
pub(crate) struct Work {
    pub yy: Vec<Real>,
    pub yp: Vec<Real>,
    pub delta: Vec<Real>,
    pub ee: Vec<Real>,
    pub ewt: Vec<Real>,
    pub rtol: Vec<Real>,
    pub atol: Vec<Real>,
    pub tmp: Vec<Real>,
    pub y_out: Vec<Real>,
    pub yp_out: Vec<Real>,
    /// Number of components in the error test.
    pub n_active: usize,
    /// ‖F‖∞ at the last residual evaluation.
    pub last_res_norm: Real,
    /// Why the last Newton iteration failed (for the statistics).
    pub fail_cause: newton::FailCause,
}

/// The BDF integrator: options, state and workspace.
#[derive(Debug, Clone)]
pub struct Bdf {
    pub(crate) opts: BdfOptions,
    pub(crate) st: BdfState,
    pub(crate) w: Work,
    /// Re-form the iteration matrix at `st.jacobian_point` before the next step (restart).
    pub(crate) needs_restore: bool,
}

impl Bdf {
    /// New integrator at (t0, y0, y0'); y0' should be consistent (see
    /// [`consistent_initial_conditions`]).
    pub fn new(opts: BdfOptions, t0: Real, y0: &[Real], yp0: &[Real]) -> Result<Self, SolverError> {
        opts.validate()?;
        if yp0.len() != y0.len() {
            return Err(SolverError::DimensionMismatch {
                what: "y0' (length of y0)",
                expected: y0.len(),
                got: yp0.len(),
            });
        }
        let st = BdfState::new(t0, y0, yp0, opts.max_order);
        Self::from_state(opts, st)
    }

    /// Continue from a saved state (see [`Bdf::state`]). The system must be the same; the
    /// iteration matrix is re-formed at the saved point on the first step.
    /// Every field of the state is checked first ([`BdfState::validate`]).
    pub fn from_state(opts: BdfOptions, st: BdfState) -> Result<Self, SolverError> {
        opts.validate()?;
        st.validate(opts.max_order)?;
        let n = st.n;
        if st.phi.len() != opts.max_order + 2 {
            return Err(SolverError::StateMismatch {
                what: "max_order + 2 (number of difference arrays)",
                state: st.phi.len(),
                expected: opts.max_order + 2,
            });
        }
        if let Some(bad) = st.phi.iter().map(|p| p.len()).find(|&l| l != n) {
            return Err(SolverError::StateMismatch {
                what: "difference array length",
                state: bad,
                expected: n,
            });
        }
        let v = || vec![0.0; n];
        let mut w = Work {
            yy: v(),
            yp: v(),
            delta: v(),
            ee: v(),
            ewt: v(),
            rtol: v(),
            atol: v(),
            tmp: v(),
            y_out: st.phi[0].clone(),
            yp_out: st.yp.clone(),
            n_active: 0,
            last_res_norm: 0.0,
            fail_cause: newton::FailCause::Other,
        };
        opts.tolerances.expand(n, &mut w.rtol, &mut w.atol)?;
        w.n_active = w.atol.iter().filter(|&&a| a < ATOL_EXCLUDED).count();
        let needs_restore = st.jacobian_point.is_some();
        Ok(Self {
            opts,
            st,
            w,
            needs_restore,
        })
    }

    /// Re-forms the iteration matrix at the restored state's saved point now (instead of on
    /// the first step), so that the system's counters can be restored after it
    /// ([`crate::bsql::BsqlSystem::restore_stats`]). A no-op when nothing is pending.
    pub fn restore_iteration_matrix<S: DaeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
    ) -> Result<(), SolverError> {
        if let Some(p) = self
            .st
            .jacobian_point
            .as_ref()
            .filter(|_| self.needs_restore)
        {
            sys.setup_jacobian(p.t, &p.y, &p.yp, p.cj)?;
        }
        self.needs_restore = false;
        Ok(())
    }

    /// A copy of the complete state, for a restart file.
    pub fn state(&self) -> &BdfState {
        &self.st
    }

    /// The options in use.
    pub fn options(&self) -> &BdfOptions {
        &self.opts
    }

    /// Counters so far.
    pub fn stats(&self) -> &BdfStats {
        &self.st.stats
    }

    /// Current internal time t_n (may be past the last output time).
    pub fn t(&self) -> Real {
        self.st.t
    }

    /// Solution at the last output time (or last step for `Interrupted`).
    pub fn y(&self) -> &[Real] {
        &self.w.y_out
    }

    /// Derivative at the last output time (or last step for `Interrupted`).
    #[allow(clippy::misnamed_getters)]
    pub fn yp(&self) -> &[Real] {
        &self.w.yp_out
    }

    /// Integrate to `tout` (IDA's normal mode: step past `tout` and interpolate), calling
    /// `on_step(system, t_n, y_n, y'_n)` after every accepted step; it returns `Ok(false)` to stop.
    /// The time spent in `on_step` (the caller's bookkeeping) is not counted in `cpu_s`.
    pub fn step_to<S, F>(
        &mut self,
        sys: &mut S,
        tout: Real,
        mut on_step: F,
    ) -> Result<Status, SolverError>
    where
        S: DaeSystem + ?Sized,
        F: FnMut(&mut S, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        let started = std::time::Instant::now();
        let mut in_callback = 0.0;
        let out = {
            let mut timed = |s: &mut S, t: Real, y: &[Real], yp: &[Real]| {
                let clock = std::time::Instant::now();
                let r = on_step(s, t, y, yp);
                in_callback += clock.elapsed().as_secs_f64();
                r
            };
            self.step_to_inner(sys, tout, &mut timed)
        };
        self.st.stats.cpu_s += (started.elapsed().as_secs_f64() - in_callback).max(0.0);
        out
    }

    /// Integrate to `tout` without a per-step callback.
    pub fn integrate_to<S: DaeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        tout: Real,
    ) -> Result<Status, SolverError> {
        self.step_to(sys, tout, |_, _, _, _| Ok(true))
    }

    fn step_to_inner<S, F>(
        &mut self,
        sys: &mut S,
        tout: Real,
        on_step: &mut F,
    ) -> Result<Status, SolverError>
    where
        S: DaeSystem + ?Sized,
        F: FnMut(&mut S, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        if sys.len() != self.st.n {
            return Err(SolverError::DimensionMismatch {
                what: "system length vs integrator state",
                expected: self.st.n,
                got: sys.len(),
            });
        }
        if !tout.is_finite() {
            return Err(SolverError::InvalidOption {
                field: "tout",
                value: tout.to_string(),
                reason: "must be finite",
            });
        }
        if self.st.h_pending {
            if tout == self.st.t {
                self.w.y_out.copy_from_slice(&self.st.phi[0]);
                self.w.yp_out.copy_from_slice(&self.st.yp);
                return Ok(Status::Reached { t: tout });
            }
            if tout < self.st.t {
                return Err(SolverError::BadOutputTime {
                    tout,
                    t_min: self.st.t,
                    t_max: Real::INFINITY,
                });
            }
            self.initial_step_size(tout);
        }
        let mut steps = 0usize;
        loop {
            if self.st.t >= tout {
                self.interpolate_into_output(tout)?;
                return Ok(Status::Reached { t: tout });
            }
            if steps >= self.opts.max_steps {
                self.interpolate_into_output(self.st.t)?;
                return Ok(Status::MaxSteps {
                    t: self.st.t,
                    steps,
                });
            }
            error_test::set_weights(&self.st.phi[0], &mut self.w);
            if let Some(status) = self.step(sys)? {
                return Ok(status);
            }
            steps += 1;
            let h_collapse = self.opts.h_collapse.unwrap_or(0.0);
            if self.st.h_used < h_collapse {
                self.st.collapse_count += 1;
            } else {
                self.st.collapse_count = 0;
            }
            let go_on = on_step(sys, self.st.t, &self.st.phi[0], &self.st.yp)?;
            if !go_on {
                self.w.y_out.copy_from_slice(&self.st.phi[0]);
                self.w.yp_out.copy_from_slice(&self.st.yp);
                return Ok(Status::Interrupted { t: self.st.t });
            }
            if self.st.collapse_count >= self.opts.collapse_steps as u64 {
                self.w.y_out.copy_from_slice(&self.st.phi[0]);
                self.w.yp_out.copy_from_slice(&self.st.yp);
                return Ok(Status::StepCollapse {
                    t: self.st.t,
                    h: self.st.h_used,
                    order: self.st.k_used,
                    h_collapse,
                    steps: self.st.collapse_count,
                });
            }
        }
    }

    /// IDA's first step: h = 0.001·|tout − t0|, reduced so that ‖h y0'‖_wrms ≤ 0.5; or `h0`,
    /// or `fixed_step`; never above `h_max`.
    fn initial_step_size(&mut self, tout: Real) {
        let mut h = if let Some(hf) = self.opts.fixed_step {
            hf
        } else if let Some(h0) = self.opts.h0 {
            h0
        } else {
            error_test::set_weights(&self.st.phi[0], &mut self.w);
            let mut h = 0.001 * (tout - self.st.t).abs();
            let ypnorm = error_test::wrms(&self.st.phi[1], &self.w);
            if ypnorm > 0.5 / h {
                h = 0.5 / ypnorm;
            }
            h
        };
        if self.opts.fixed_step.is_none() {
            h = h.min(self.opts.h_max.unwrap_or(Real::INFINITY));
        }
        self.st.h = h;
        for x in self.st.phi[1].iter_mut() {
            *x *= h;
        }
        self.st.h_pending = false;
    }
}
