//! The integrator of a run, BDF or generalized-α, with its BSQL system: one [`Stepper`] that
//! the driver steps and asks for its state and counters. It knows nothing of sinks or
//! checkpoints.

use super::restart::RestartFile;
use crate::error::PipelineError;
use crate::problem::options::{bdf_options, galpha_options};
use crate::problem::recover::{BandStart, FullView};
use crate::problem::system::{solver_err, GapFriction, Problem};
use crate::scene::{Integrator, TransientSpec};
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_solver::bdf::{Bdf, BdfState, BdfStats, Status};
use squeal_solver::bsql::{
    BsqlStats, BsqlSystem, EventRestart, Unilateral, UnilateralOptions, UnilateralStats,
};
use squeal_solver::condense::BandSystem;
use squeal_solver::galpha::{Galpha, GalphaStats, GalphaSystem};
use squeal_solver::Real;
use squeal_solver::SolverError;
use std::path::Path;

/// Integrator and accuracy setting of one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "integrator", rename_all = "snake_case")]
pub enum Method {
    /// BDF with RTOL1 = `rtol` (ATOL1 scaled by rtol / scene RTOL1) and MAXORD.
    Bdf { rtol: Real, max_order: usize },
    /// Generalized-α: fixed step `h`, or adaptive with `rtol` when `h` is None.
    GeneralizedAlpha {
        h: Option<Real>,
        rtol: Real,
        rho_inf: Real,
    },
}

impl Method {
    /// The method the scene's `[transient]` table asks for.
    pub fn of_spec(spec: &TransientSpec) -> Self {
        match spec.integrator {
            Integrator::Bdf => Method::Bdf {
                rtol: spec.rtol1,
                max_order: spec.maxord,
            },
            Integrator::GeneralizedAlpha => Method::GeneralizedAlpha {
                h: spec.galpha_h,
                rtol: spec.rtol1,
                rho_inf: spec.rho_inf,
            },
        }
    }

    /// Which integrator.
    pub fn integrator(&self) -> Integrator {
        match self {
            Method::Bdf { .. } => Integrator::Bdf,
            Method::GeneralizedAlpha { .. } => Integrator::GeneralizedAlpha,
        }
    }
}

/// The integrator of a run with its system. The BDF's BSQL system also observes the energy
/// terms; generalized-α integrates its own system and a BSQL system observes.
#[allow(clippy::large_enum_variant)] // one per run, never moved in a loop
pub enum Stepper {
    Bdf {
        bdf: Bdf,
        sys: BsqlSystem<GapFriction>,
        /// Separation events (`[[contact]] separation = true`), None when off.
        uni: Option<Unilateral>,
    },
    GeneralizedAlpha {
        ga: Galpha,
        sys: GalphaSystem<GapFriction>,
        obs: BsqlSystem<GapFriction>,
    },
    /// BDF on the band-limited model (`transient.band_limited`); a BSQL system observes the
    /// full model's variables recovered from it.
    Band {
        bdf: Bdf,
        sys: BandSystem<GapFriction>,
        obs: BsqlSystem<GapFriction>,
        full: FullView,
    },
}

/// The integrator's counters, whichever it is.
// Counters, built once per run and serialised: the BDF variant's size does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "integrator", rename_all = "snake_case")]
pub enum IntegratorStats {
    Bdf {
        bdf: BdfStats,
        bsql: BsqlStats,
        /// Separation events (None when separation is off).
        #[serde(skip_serializing_if = "Option::is_none")]
        separation: Option<UnilateralStats>,
    },
    GeneralizedAlpha {
        galpha: GalphaStats,
    },
}

impl IntegratorStats {
    /// Accepted steps (cumulative over restarts).
    pub fn steps(&self) -> u64 {
        match self {
            IntegratorStats::Bdf { bdf, .. } => bdf.steps,
            IntegratorStats::GeneralizedAlpha { galpha } => galpha.steps,
        }
    }

    /// Seconds inside the integrator.
    pub fn cpu_s(&self) -> Real {
        match self {
            IntegratorStats::Bdf { bdf, .. } => bdf.cpu_s,
            IntegratorStats::GeneralizedAlpha { galpha } => galpha.cpu_s,
        }
    }

    /// (last, largest) ‖G v‖∞ the integrator's system saw.
    pub fn constraint_drift(&self) -> (Real, Real) {
        match self {
            IntegratorStats::Bdf { bsql, .. } => (bsql.constraint_drift, bsql.max_constraint_drift),
            IntegratorStats::GeneralizedAlpha { galpha } => {
                (galpha.constraint_drift, galpha.max_constraint_drift)
            }
        }
    }
}

impl Stepper {
    /// A new integrator at (t0, y0, y0') for `method`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        problem: &Problem,
        spec: &TransientSpec,
        method: Method,
        t0: Real,
        y0: &[Real],
        yp0: &[Real],
        tfinal: Real,
    ) -> Result<Self, PipelineError> {
        let n = problem.m.nrows();
        let ng = problem.g.nrows();
        match method {
            Method::Bdf { rtol, max_order } => {
                let sys = problem.system(problem.gaps.clone())?;
                let bdf = Bdf::new(bdf_options(spec, &sys, rtol, max_order), t0, y0, yp0)
                    .map_err(solver_err("integrator"))?;
                Ok(Stepper::Bdf {
                    bdf,
                    sys,
                    uni: None,
                })
            }
            Method::GeneralizedAlpha { h, rtol, rho_inf } => {
                let obs = problem.system(problem.gaps.clone())?;
                let mut sys = GalphaSystem::new(
                    problem.m.clone(),
                    problem.b.clone(),
                    problem.k.clone(),
                    problem.g.clone(),
                    problem.load.clone(),
                    GapFriction {
                        set: problem.gaps.clone(),
                    },
                )
                .map_err(solver_err("building the generalized-alpha system"))?;
                let opts = galpha_options(spec, n, ng, h, rtol, rho_inf, tfinal);
                let ga = Galpha::new(opts, &mut sys, t0, y0, yp0)
                    .map_err(solver_err("generalized-alpha start"))?;
                Ok(Stepper::GeneralizedAlpha { ga, sys, obs })
            }
        }
    }

    /// BDF on the band-limited model `sys` ([`BandStart`]); returns the largest residual of
    /// its initial values too.
    pub fn band(
        problem: &Problem,
        spec: &TransientSpec,
        sys: BandSystem<GapFriction>,
    ) -> Result<(Self, Real), PipelineError> {
        let b = BandStart::new(problem, spec, sys)?;
        let (bdf, sys, obs, full) = (b.bdf, b.sys, b.obs, b.full);
        Ok((
            Stepper::Band {
                bdf,
                sys,
                obs,
                full,
            },
            b.residual,
        ))
    }

    /// A BDF integrator continuing a restart file's state (`path`: the file, named in errors).
    ///
    /// `stats`: the BSQL counters of the run that wrote it (from its checkpoint), restored
    /// after the iteration matrix is re-formed at the saved point.
    pub fn from_restart(
        problem: &Problem,
        spec: &TransientSpec,
        restart: RestartFile,
        stats: Option<BsqlStats>,
        path: &Path,
    ) -> Result<Self, PipelineError> {
        let mut sys = problem.system(problem.gaps.clone())?;
        let mut bdf = restart.bdf(path, bdf_options(spec, &sys, spec.rtol1, spec.maxord))?;
        if let Some(stats) = stats {
            // The matrix the run last formed, re-formed now, then the run's counters: the
            // resumed run counts as the uninterrupted one does.
            bdf.restore_iteration_matrix(&mut sys)
                .map_err(|e| PipelineError::Input {
                    path: path.to_path_buf(),
                    message: format!("field `state.jacobian_point`: {e}"),
                })?;
            sys.restore_stats(stats);
        }
        Ok(Stepper::Bdf {
            bdf,
            sys,
            uni: None,
        })
    }

    /// Let the gaps with `can_open[k]` separate and close again (events, plastic impact,
    /// restart as `restart` says; see [`squeal_solver::bsql::unilateral`]). An open gap carries
    /// λ' = P_0 A (p_n = 0). BDF only: generalized-α gets an error naming the option.
    pub fn enable_separation(
        &mut self,
        gaps: &GapSet,
        can_open: Vec<bool>,
        restart: EventRestart,
    ) -> Result<(), PipelineError> {
        match self {
            Stepper::Bdf { bdf, sys, uni } => {
                let open_force = gaps.gaps.iter().map(|g| g.p0 * g.area).collect();
                let (y, yp) = (bdf.y().to_vec(), bdf.yp().to_vec());
                *uni = Some(
                    Unilateral::new(
                        sys,
                        open_force,
                        Some(can_open),
                        &y,
                        &yp,
                        UnilateralOptions {
                            restart,
                            ..UnilateralOptions::default()
                        },
                    )
                    .map_err(solver_err("separation"))?,
                );
                Ok(())
            }
            Stepper::Band { .. } => Err(PipelineError::Scene {
                field: "contact[].separation".into(),
                message: "the band-limited model opens compliant gaps without events".into(),
            }),
            Stepper::GeneralizedAlpha { .. } => Err(PipelineError::Scene {
                field: "contact[].separation".into(),
                message: "separation events need the BDF integrator \
                          (transient.integrator = \"bdf\")"
                    .into(),
            }),
        }
    }

    /// Kinetic energy lost in the plastic impacts so far (0 without separation).
    pub fn impact_dissipated(&self) -> Real {
        match self {
            Stepper::Bdf { uni: Some(u), .. } => u.stats().impact_dissipated,
            _ => 0.0,
        }
    }

    /// Which integrator.
    pub fn integrator(&self) -> Integrator {
        match self {
            Stepper::Bdf { .. } | Stepper::Band { .. } => Integrator::Bdf,
            Stepper::GeneralizedAlpha { .. } => Integrator::GeneralizedAlpha,
        }
    }

    /// Time of the solution in `y()`.
    pub fn t(&self) -> Real {
        match self {
            Stepper::Bdf { bdf, .. } | Stepper::Band { bdf, .. } => bdf.t(),
            Stepper::GeneralizedAlpha { ga, .. } => ga.t(),
        }
    }

    /// y = {v, λ, u} at the last step or output time.
    pub fn y(&self) -> &[Real] {
        match self {
            Stepper::Bdf { bdf, .. } => bdf.y(),
            Stepper::Band { full, .. } => &full.y,
            Stepper::GeneralizedAlpha { ga, .. } => ga.y(),
        }
    }

    /// y' at the last step or output time.
    pub fn yp(&self) -> &[Real] {
        match self {
            Stepper::Bdf { bdf, .. } => bdf.yp(),
            Stepper::Band { full, .. } => &full.yp,
            Stepper::GeneralizedAlpha { ga, .. } => ga.yp(),
        }
    }

    /// Step size of the next step, and the BDF order (2 for generalized-α).
    pub fn h_order(&self) -> (Real, usize) {
        match self {
            Stepper::Bdf { bdf, .. } | Stepper::Band { bdf, .. } => {
                (bdf.state().h, bdf.state().order)
            }
            Stepper::GeneralizedAlpha { ga, .. } => (ga.h(), 2),
        }
    }

    /// The BDF's complete state (None for generalized-α: no restart).
    pub fn bdf_state(&self) -> Option<&BdfState> {
        match self {
            Stepper::Bdf { bdf, .. } => Some(bdf.state()),
            // The band state is not the reduced model's: no restart file.
            Stepper::Band { .. } | Stepper::GeneralizedAlpha { .. } => None,
        }
    }

    /// The BDF's accepted steps by order so far (None for generalized-α).
    pub fn order_histogram(&self) -> Option<&[u64]> {
        match self {
            Stepper::Bdf { bdf, .. } | Stepper::Band { bdf, .. } => {
                Some(&bdf.stats().order_histogram)
            }
            Stepper::GeneralizedAlpha { .. } => None,
        }
    }

    /// Counters so far.
    pub fn stats(&self) -> IntegratorStats {
        match self {
            Stepper::Bdf { bdf, sys, uni } => IntegratorStats::Bdf {
                bdf: bdf.stats().clone(),
                bsql: sys.stats().clone(),
                separation: uni.as_ref().map(|u| u.stats().clone()),
            },
            Stepper::Band { bdf, obs, .. } => IntegratorStats::Bdf {
                bdf: bdf.stats().clone(),
                bsql: obs.stats().clone(),
                separation: None,
            },
            Stepper::GeneralizedAlpha { ga, .. } => IntegratorStats::GeneralizedAlpha {
                galpha: ga.stats().clone(),
            },
        }
    }

    /// The BSQL system that observes energies.
    pub(super) fn observer(&mut self) -> &mut BsqlSystem<GapFriction> {
        match self {
            Stepper::Bdf { sys, .. } => sys,
            Stepper::GeneralizedAlpha { obs, .. } | Stepper::Band { obs, .. } => obs,
        }
    }

    /// Integrates to `tout`, calling `on_step(observer, t, y, y')` after every accepted step.
    pub(super) fn step_to<F>(&mut self, tout: Real, mut on_step: F) -> Result<Status, SolverError>
    where
        F: FnMut(&mut BsqlSystem<GapFriction>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        match self {
            Stepper::Bdf {
                bdf,
                sys,
                uni: Some(u),
            } => u.step_to(bdf, sys, tout, on_step),
            Stepper::Bdf {
                bdf,
                sys,
                uni: None,
            } => bdf.step_to(sys, tout, on_step),
            Stepper::GeneralizedAlpha { ga, sys, obs } => {
                ga.step_to(sys, tout, |_, t, y, yp| on_step(obs, t, y, yp))
            }
            Stepper::Band {
                bdf,
                sys,
                obs,
                full,
            } => full.step_to(bdf, sys, obs, tout, on_step),
        }
    }
}
