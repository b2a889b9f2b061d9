//! The band-limited run's start and the full model's variables recovered from its state
//! (`transient.band_limited`): what `stages::transient::stepper::Stepper::Band` holds besides the BDF.

use super::options::bdf_options;
use super::system::{solver_err, GapFriction, Problem};
use crate::error::PipelineError;
use crate::scene::TransientSpec;
use squeal_solver::bdf::{Bdf, BdfOptions, DaeSystem, Status};
use squeal_solver::bsql::BsqlSystem;
use squeal_solver::condense::BandSystem;
use squeal_solver::{Real, SolverError};

/// A band-limited run at its start: the BDF from the band system's steady state before the
/// brake load (t = −1) and its initial values at t0 = 0 (RTOL1/ATOL1 on its states and
/// contact velocities, RTOL2/ATOL2 on its normal forces), the BSQL system that observes the
/// energies, the recovered full variables, and the initial values' largest residual.
pub struct BandStart {
    pub bdf: Bdf,
    pub sys: BandSystem<GapFriction>,
    pub obs: BsqlSystem<GapFriction>,
    pub full: FullView,
    pub residual: Real,
}

impl BandStart {
    /// The start of a run of `sys` for the scene's `[transient]` `spec`.
    pub fn new(
        problem: &Problem,
        spec: &TransientSpec,
        mut sys: BandSystem<GapFriction>,
    ) -> Result<Self, PipelineError> {
        let (y0, yp0) = sys.initial_values(-1.0, 0.0).map_err(solver_err(
            "band-limited model: steady state and initial values",
        ))?;
        let mut res = vec![0.0; y0.len()];
        sys.residual(0.0, &y0, &yp0, &mut res)
            .map_err(solver_err("band-limited model: initial residual"))?;
        let residual = res.iter().fold(0.0, |m: Real, r| m.max(r.abs()));
        let obs = problem.system(problem.gaps.clone())?;
        let opts = BdfOptions {
            tolerances: sys.tolerances(spec.rtol1, spec.atol1, spec.rtol2, spec.atol2),
            ..bdf_options(spec, &obs, spec.rtol1, spec.maxord)
        };
        let bdf = Bdf::new(opts, 0.0, &y0, &yp0).map_err(solver_err("integrator"))?;
        let mut full = FullView::new(problem.m.nrows(), problem.g.nrows());
        full.fill(&mut sys, 0.0, &y0, &yp0)
            .map_err(solver_err("band-limited model: recovery"))?;
        Ok(Self {
            bdf,
            sys,
            obs,
            full,
            residual,
        })
    }
}

/// The full model's y = {v, λ, u} and y' recovered from the band-limited state: u, v by the
/// condensed model's maps, λ' its contact forces, v' its modal part (the static correction's
/// rate left out), λ the impulses integrated by the trapezoidal rule.
pub struct FullView {
    n: usize,
    pub t: Real,
    pub y: Vec<Real>,
    pub yp: Vec<Real>,
    u: Vec<Real>,
    v: Vec<Real>,
    lam: Vec<Real>,
    vp: Vec<Real>,
}

impl FullView {
    pub fn new(n: usize, ng: usize) -> Self {
        Self {
            n,
            t: Real::NAN,
            y: vec![0.0; 2 * n + ng],
            yp: vec![0.0; 2 * n + ng],
            u: vec![0.0; n],
            v: vec![0.0; n],
            lam: vec![0.0; ng],
            vp: vec![0.0; n],
        }
    }

    /// Recovers the full variables at (t, y_band, y_band').
    pub fn fill(
        &mut self,
        sys: &mut BandSystem<GapFriction>,
        t: Real,
        yb: &[Real],
        ypb: &[Real],
    ) -> Result<(), SolverError> {
        let n = self.n;
        let ng = self.lam.len();
        sys.physical(
            t,
            yb,
            ypb,
            &mut self.u,
            &mut self.v,
            &mut self.lam,
            Some(&mut self.vp),
        )?;
        let dt = if self.t.is_finite() { t - self.t } else { 0.0 };
        for k in 0..ng {
            self.y[n + k] += 0.5 * dt * (self.yp[n + k] + self.lam[k]);
            self.yp[n + k] = self.lam[k];
        }
        self.t = t;
        self.y[..n].copy_from_slice(&self.v);
        self.y[n + ng..].copy_from_slice(&self.u);
        self.yp[..n].copy_from_slice(&self.vp);
        self.yp[n + ng..].copy_from_slice(&self.v);
        Ok(())
    }

    /// Integrates `sys` to `tout`, calling `on_step(obs, t, y, y')` with the recovered full
    /// variables after every accepted step.
    pub fn step_to<F>(
        &mut self,
        bdf: &mut Bdf,
        sys: &mut BandSystem<GapFriction>,
        obs: &mut BsqlSystem<GapFriction>,
        tout: Real,
        mut on_step: F,
    ) -> Result<Status, SolverError>
    where
        F: FnMut(&mut BsqlSystem<GapFriction>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        let st = bdf.step_to(sys, tout, |s, t, y, yp| {
            self.fill(s, t, y, yp)?;
            on_step(obs, t, &self.y, &self.yp)
        })?;
        // At an output time between steps the BDF interpolates: recover that point.
        if bdf.t() != self.t {
            let (y, yp) = (bdf.y().to_vec(), bdf.yp().to_vec());
            self.fill(sys, bdf.t(), &y, &yp)?;
        }
        Ok(st)
    }
}
